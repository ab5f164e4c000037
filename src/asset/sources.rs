//! The bytes a glTF document draws on: the document parsed (a GLB split without copying its binary
//! chunk), its buffers read once per distinct source, and its images decoded once per distinct source, all
//! charged to the load's [`Meter`] before the memory is taken.
//!
//! Why: a file may name one source many times (eight buffers naming one 512 MiB file, twelve images naming
//! one 8192x8192 PNG); reading and decoding per name multiplies memory by the number of names. Sources are
//! keyed by what they resolve to: the GLB chunk, a `data:` URI's text, a file's canonical path, a buffer
//! view's byte range.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::PathBuf;

use super::budget::{Limit, Meter};
use super::error::{AssetError, BufferProblem, ImageProblem, ParseError, Place};
use super::uri::{Base, Located, locate};
use crate::render::Texture;

/// Largest texture side accepted.
pub const MAX_IMAGE_SIDE: u32 = 8192;
/// Most bytes one image may take while decoding (the `image` crate's allocation limit).
pub const MAX_DECODE_BYTES: u64 = 512 << 20;

/// A parsed and validated document with the GLB binary chunk, if any, borrowed from the file's bytes.
pub struct Parsed<'a> {
    /// The validated document.
    pub doc: gltf::Document,
    /// The GLB `BIN` chunk (the bytes of buffer 0 when it has no URI).
    pub blob: Option<Cow<'a, [u8]>>,
}

/// Parses glTF JSON or a GLB container and validates the document.
pub fn parse(bytes: &[u8]) -> Result<Parsed<'_>, ParseError> {
    let (json, blob): (Cow<'_, [u8]>, _) = if bytes.starts_with(b"glTF") {
        // `Glb::from_slice` subtracts the 12-byte header from the declared length without checking it
        // (an overflow panic in debug builds), so a length under 12 is refused here first.
        let declared = bytes.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        match declared {
            Some(n) if n >= 12 => {}
            Some(declared) => return Err(ParseError::GlbLength { declared }),
            None => return Err(ParseError::GlbCut),
        }
        let glb = gltf::Glb::from_slice(bytes).map_err(ParseError::Gltf)?;
        (glb.json, glb.bin)
    } else {
        (Cow::Borrowed(bytes), None)
    };
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(&json).map_err(|e| ParseError::Gltf(gltf::Error::Deserialize(e)))?;
    super::validate::check_before_validation(&root)?;
    let doc = validated(root).map_err(ParseError::Gltf)?;
    Ok(Parsed { doc, blob })
}

/// The `gltf` crate's validation of `root`, less its one error that the specification contradicts: an
/// accessor with neither `bufferView` nor `sparse` is valid glTF 2.0 ("When bufferView is undefined, the
/// accessor MUST be initialized with zeros"), and [`super::accessor`] reads it as zeros.
fn validated(root: gltf::json::Root) -> Result<gltf::Document, gltf::Error> {
    use gltf::json::validation::{Error, Validate};
    let mut errors = vec![];
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let zeros = matches!(error, Error::Missing)
            && path.as_str().strip_prefix("accessors[").and_then(|rest| rest.strip_suffix("].bufferView")).is_some();
        if !zeros {
            errors.push((path, error));
        }
    });
    if errors.is_empty() {
        Ok(gltf::Document::from_json_without_validation(root))
    } else {
        Err(gltf::Error::Validation(errors))
    }
}

/// What a buffer or image resolves to, so that two names of one source share it.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Key<'d> {
    Bin,
    Data(&'d str),
    Embedded(String),
    File(PathBuf),
    View { buffer: usize, start: usize, end: usize },
}

/// The buffers' bytes, each distinct source held once.
#[derive(Debug, Default)]
pub struct Buffers<'a> {
    data: Vec<Cow<'a, [u8]>>,
    /// glTF buffer index -> index into `data`.
    slot: Vec<usize>,
    /// The files read (canonical paths), each once.
    files: Vec<PathBuf>,
}

impl Buffers<'_> {
    /// Each glTF buffer's bytes, by buffer index.
    #[must_use]
    pub fn slices(&self) -> Vec<&[u8]> {
        self.slot.iter().map(|&s| self.data.get(s).map_or(&[][..], |d| &d[..])).collect()
    }

    /// The files read for the buffers (canonical paths), each once.
    pub fn files(&self) -> impl Iterator<Item = &PathBuf> {
        self.files.iter()
    }
}

/// Reads every buffer of `doc`: all sources are located and their sizes charged to
/// [`crate::asset::LoadBudget::buffer_bytes`] before any is read; a source named by several buffers is
/// read once; the GLB chunk is taken, not copied.
pub fn load_buffers<'a>(
    doc: &gltf::Document,
    blob: Option<Cow<'a, [u8]>>,
    base: Base<'_>,
    meter: &mut Meter,
    file: &str,
) -> Result<Buffers<'a>, AssetError> {
    let err = |index: usize, problem: BufferProblem| AssetError::Buffer { file: file.to_string(), index, problem };
    let mut keys: BTreeMap<Key<'_>, usize> = BTreeMap::new();
    let mut pending: Vec<(usize, Option<Located<'_>>)> = vec![];
    let mut slot = Vec::with_capacity(doc.buffers().len());
    for b in doc.buffers() {
        let (key, located) = match b.source() {
            gltf::buffer::Source::Bin => (Key::Bin, None),
            gltf::buffer::Source::Uri(uri) => {
                let located = locate(uri, base).map_err(|e| err(b.index(), e.into()))?;
                let key = match &located {
                    Located::File { path, .. } => Key::File(path.clone()),
                    Located::Embedded { name, .. } => Key::Embedded(name.clone()),
                    Located::Data { .. } => Key::Data(uri),
                };
                (key, Some(located))
            }
        };
        let size = match &located {
            Some(l) => l.size_bound(),
            None => blob.as_ref().map_or(0, |d| d.len() as u64),
        };
        if let Some(Located::File { size, .. }) = &located
            && *size < b.length() as u64
        {
            return Err(err(b.index(), BufferProblem::Short { holds: *size, declared: b.length() }));
        }
        let next = keys.len();
        let s = *keys.entry(key).or_insert(next);
        if s == next {
            meter
                .charge(Limit::BufferBytes, size)
                .map_err(|over| AssetError::budget(file, Place::Buffer(b.index()), over))?;
            pending.push((b.index(), located));
        }
        slot.push(s);
    }
    let mut blob = blob;
    let mut data = Vec::with_capacity(pending.len());
    let mut files = vec![];
    for (index, located) in pending {
        if let Some(Located::File { path, .. }) = &located {
            files.push(path.clone());
        }
        let bytes = match located {
            Some(l) => Cow::Owned(l.read().map_err(|e| err(index, e.into()))?),
            None => blob.take().ok_or_else(|| err(index, BufferProblem::NoBinaryChunk))?,
        };
        data.push(bytes);
    }
    for (b, &s) in doc.buffers().zip(&slot) {
        let len = data.get(s).map_or(0, |d| d.len());
        if len < b.length() {
            return Err(err(b.index(), BufferProblem::Short { holds: len as u64, declared: b.length() }));
        }
    }
    Ok(Buffers { data, slot, files })
}

/// Textures decoded so far, by glTF image index and by source.
#[derive(Debug, Default)]
pub struct Images<'d> {
    by_image: BTreeMap<usize, usize>,
    by_key: BTreeMap<Key<'d>, usize>,
}

impl<'d> Images<'d> {
    /// The files decoded (canonical paths), each once.
    pub fn files(&self) -> impl Iterator<Item = &PathBuf> {
        self.by_key.keys().filter_map(|k| match k {
            Key::File(path) => Some(path),
            _ => None,
        })
    }

    /// The texture index for glTF image `index`, decoding it into `textures` the first time its source is
    /// seen. Reads the image's fields from the raw JSON (see [`super::validate`]).
    pub fn texture(
        &mut self,
        doc: &'d gltf::Document,
        index: usize,
        ctx: (&[&[u8]], Base<'_>, &str),
        meter: &mut Meter,
        textures: &mut Vec<Texture>,
    ) -> Result<usize, AssetError> {
        let (buffers, base, file) = ctx;
        if let Some(&t) = self.by_image.get(&index) {
            return Ok(t);
        }
        let err = |problem: ImageProblem| AssetError::Image { file: file.to_string(), index, problem };
        let json = doc.as_json().images.get(index).ok_or_else(|| err(ImageProblem::Missing))?;
        let (key, bytes): (Key<'d>, Option<Cow<'_, [u8]>>) = match (&json.buffer_view, &json.uri) {
            (Some(v), _) => {
                let view = doc.views().nth(v.value()).ok_or_else(|| err(ImageProblem::MissingView))?;
                let buf = buffers.get(view.buffer().index()).ok_or_else(|| err(ImageProblem::ViewMissingBuffer))?;
                let end = view.offset().checked_add(view.length()).ok_or_else(|| err(ImageProblem::ViewOverflow))?;
                let bytes = buf.get(view.offset()..end).ok_or_else(|| {
                    let (view, start, buffer_len) = (view.index(), view.offset(), buf.len());
                    err(ImageProblem::ViewPastBuffer { view, start, end, buffer_len })
                })?;
                (Key::View { buffer: view.buffer().index(), start: view.offset(), end }, Some(Cow::Borrowed(bytes)))
            }
            (None, Some(uri)) => {
                let located = locate(uri, base).map_err(|e| err(e.into()))?;
                let key = match &located {
                    Located::File { path, .. } => Key::File(path.clone()),
                    Located::Embedded { name, .. } => Key::Embedded(name.clone()),
                    Located::Data { .. } => Key::Data(uri),
                };
                if let Some(&t) = self.by_key.get(&key) {
                    self.by_image.insert(index, t);
                    return Ok(t);
                }
                meter
                    .charge(Limit::ImageBytes, located.size_bound())
                    .map_err(|over| AssetError::budget(file, Place::Image(index), over))?;
                (key, Some(Cow::Owned(located.read().map_err(|e| err(e.into()))?)))
            }
            (None, None) => return Err(err(ImageProblem::NoSource)),
        };
        let t = match self.by_key.get(&key) {
            Some(&t) => t,
            None => {
                let bytes = bytes.unwrap_or_default();
                let texture = decode_image(&bytes, meter).map_err(|e| match e {
                    Decode::Bad(problem) => err(problem),
                    Decode::Over(over) => AssetError::budget(file, Place::Image(index), over),
                })?;
                textures.push(texture);
                self.by_key.insert(key, textures.len() - 1);
                textures.len() - 1
            }
        };
        self.by_image.insert(index, t);
        Ok(t)
    }
}

/// Why an image did not decode: the image is wrong, or it needs more than the budget.
enum Decode {
    Bad(ImageProblem),
    Over(super::budget::OverBudget),
}

/// Decodes PNG or JPEG bytes into a texture: the size is read from the header first and refused over
/// [`MAX_IMAGE_SIDE`] or the texel budget before any pixel is decoded.
fn decode_image(bytes: &[u8], meter: &mut Meter) -> Result<Texture, Decode> {
    let bad = |e: image::ImageError| Decode::Bad(ImageProblem::Decode(e));
    let reader = || {
        image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| Decode::Bad(ImageProblem::Format(e)))
    };
    let (width, height) = reader()?.into_dimensions().map_err(bad)?;
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(Decode::Bad(ImageProblem::TooBig { width, height, limit: MAX_IMAGE_SIDE }));
    }
    meter.charge(Limit::Texels, u64::from(width) * u64::from(height)).map_err(Decode::Over)?;
    let mut reader = reader()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    let rgba = reader.decode().map_err(bad)?.into_rgba8();
    Texture::from_rgba8(rgba.width(), rgba.height(), rgba.as_raw()).map_err(|e| Decode::Bad(e.into()))
}
