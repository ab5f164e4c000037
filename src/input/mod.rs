//! Input: turning devices into per-tick [`crate::game::Controls`], and the trace format that records them
//! and replays them through the same seam.

pub mod bindings;
pub mod gamepad;
pub mod ghost;
pub mod header;
pub mod pad_names;
pub mod recording;
pub mod replay;
pub mod trace;
