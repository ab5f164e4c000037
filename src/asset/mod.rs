//! Loading glTF 2.0 assets.
