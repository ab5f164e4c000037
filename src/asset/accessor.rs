//! Reading glTF accessors with every offset, stride and count checked, so a hostile file gets an error
//! instead of a panic or an out-of-bounds read.

use std::collections::BTreeMap;
use std::rc::Rc;

use gltf::accessor::{DataType, Dimensions};
use thiserror::Error;

/// Most elements one accessor may hold (16 Mi): bounds memory for hostile counts.
pub const MAX_ELEMENTS: usize = 1 << 24;

/// An accessor's elements, each widened to `f32` components (normalised integers scaled to `0..=1` or `-1..=1`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Elements {
    /// Components per element.
    pub width: usize,
    /// `count * width` values.
    pub values: Vec<f32>,
}

impl Elements {
    /// Number of elements.
    #[must_use]
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.width).unwrap_or(0)
    }
    /// True when there are no elements.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Element `i`, component `c`, or 0 when out of range.
    #[must_use]
    pub fn get(&self, i: usize, c: usize) -> f32 {
        if c < self.width { self.values.get(i * self.width + c).copied().unwrap_or(0.0) } else { 0.0 }
    }
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn read_component(bytes: &[u8], t: DataType, normalized: bool) -> f32 {
    let b = |n: usize| bytes.get(n).copied().unwrap_or(0);
    match t {
        DataType::I8 => {
            let v = f32::from(b(0) as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f32::from(b(0));
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([b(0), b(1)]));
            if normalized { (v / 32767.0).max(-1.0) } else { v }
        }
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([b(0), b(1)]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f32,
        DataType::F32 => f32::from_le_bytes([b(0), b(1), b(2), b(3)]),
    }
}

fn read_index(bytes: &[u8], t: DataType) -> Option<u32> {
    match t {
        DataType::U8 => bytes.first().map(|&v| u32::from(v)),
        DataType::U16 => Some(u32::from(u16::from_le_bytes([*bytes.first()?, *bytes.get(1)?]))),
        DataType::U32 => Some(u32::from_le_bytes([*bytes.first()?, *bytes.get(1)?, *bytes.get(2)?, *bytes.get(3)?])),
        _ => None,
    }
}

/// Why an accessor could not be read: the accessor, and what about its ranges is wrong.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("accessor {accessor}: {problem}")]
pub struct AccessorError {
    /// glTF accessor index.
    pub accessor: usize,
    /// What is wrong.
    pub problem: AccessorProblem,
}

/// What is wrong with an accessor's ranges or types.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum AccessorProblem {
    /// A buffer view names a buffer the file does not have.
    #[error("buffer view refers to a missing buffer")]
    MissingBuffer,
    /// A buffer view's offset plus length overflows.
    #[error("buffer view range overflows")]
    ViewOverflow,
    /// A buffer view runs past the end of its buffer.
    #[error("buffer view {view} (bytes {start}..{end}) runs past its buffer of {buffer_len} bytes")]
    ViewPastBuffer {
        /// glTF buffer view index.
        view: usize,
        /// First byte.
        start: usize,
        /// One past the last byte.
        end: usize,
        /// The buffer's length.
        buffer_len: usize,
    },
    /// The accessor's last byte overflows.
    #[error("accessor range overflows")]
    RangeOverflow,
    /// The accessor needs more bytes than its view has.
    #[error("accessor needs {needed} bytes of its buffer view, which has {available}")]
    PastView {
        /// Bytes needed.
        needed: usize,
        /// Bytes in the view.
        available: usize,
    },
    /// More elements than any accessor may hold.
    #[error("{count} elements exceed the limit of {limit}")]
    TooMany {
        /// Elements declared.
        count: usize,
        /// [`MAX_ELEMENTS`].
        limit: usize,
    },
    /// The byte stride is smaller than one element.
    #[error("byte stride {stride} is smaller than the element size {element}")]
    StrideTooSmall {
        /// Declared stride.
        stride: usize,
        /// Element size in bytes.
        element: usize,
    },
    /// A sparse accessor overrides more elements than the accessor has.
    #[error("sparse accessor overrides {overrides} of only {count} elements")]
    SparseTooMany {
        /// Overridden elements.
        overrides: usize,
        /// The accessor's elements.
        count: usize,
    },
    /// A sparse index names an element past the accessor's end.
    #[error("sparse index {index} is out of range for {count} elements")]
    SparseIndex {
        /// The index.
        index: usize,
        /// The accessor's elements.
        count: usize,
    },
    /// An index accessor is not an unsigned scalar.
    #[error("indices must be unsigned scalars")]
    NotUnsignedScalars,
}

/// The bytes of a buffer view, checked against its buffer.
fn view_bytes<'b>(view: &gltf::buffer::View<'_>, buffers: &[&'b [u8]]) -> Result<&'b [u8], AccessorProblem> {
    let buf: &'b [u8] = buffers.get(view.buffer().index()).ok_or(AccessorProblem::MissingBuffer)?;
    let end = view.offset().checked_add(view.length()).ok_or(AccessorProblem::ViewOverflow)?;
    buf.get(view.offset()..end).ok_or(AccessorProblem::ViewPastBuffer {
        view: view.index(),
        start: view.offset(),
        end,
        buffer_len: buf.len(),
    })
}

/// Walks `count` strided elements of `elem` bytes from `offset` in a view's bytes, checking the range first.
fn strided<'b>(
    bytes: &'b [u8],
    offset: usize,
    stride: usize,
    elem: usize,
    count: usize,
) -> Result<impl Iterator<Item = &'b [u8]> + 'b, AccessorProblem> {
    if count > 0 {
        let last = stride
            .checked_mul(count - 1)
            .and_then(|v| v.checked_add(offset))
            .and_then(|v| v.checked_add(elem))
            .ok_or(AccessorProblem::RangeOverflow)?;
        if last > bytes.len() {
            return Err(AccessorProblem::PastView { needed: last, available: bytes.len() });
        }
    }
    Ok((0..count).map(move |i| &bytes[offset + i * stride..offset + i * stride + elem]))
}

/// Accessors read so far, so that one shared by several primitives or meshes is read (and charged) once.
#[derive(Debug, Default)]
pub struct AccessorCache {
    pub(crate) floats: BTreeMap<usize, Rc<Elements>>,
    pub(crate) indices: BTreeMap<usize, Rc<Vec<u32>>>,
}

/// Reads an accessor as `f32` components; errors name the accessor.
pub fn read_floats(acc: &gltf::Accessor<'_>, buffers: &[&[u8]]) -> Result<Elements, AccessorError> {
    read_floats_inner(acc, buffers).map_err(|problem| AccessorError { accessor: acc.index(), problem })
}

fn read_floats_inner(acc: &gltf::Accessor<'_>, buffers: &[&[u8]]) -> Result<Elements, AccessorProblem> {
    let count = acc.count();
    if count > MAX_ELEMENTS {
        return Err(AccessorProblem::TooMany { count, limit: MAX_ELEMENTS });
    }
    let width = acc.dimensions().multiplicity();
    let t = acc.data_type();
    let cs = component_size(t);
    let elem = cs * width;
    let mut values = vec![0.0f32; count * width];
    if let Some(view) = acc.view() {
        let bytes = view_bytes(&view, buffers)?;
        let stride = view.stride().unwrap_or(elem);
        if stride < elem {
            return Err(AccessorProblem::StrideTooSmall { stride, element: elem });
        }
        for (i, e) in strided(bytes, acc.offset(), stride, elem, count)?.enumerate() {
            for c in 0..width {
                values[i * width + c] = read_component(&e[c * cs..], t, acc.normalized());
            }
        }
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n > count {
            return Err(AccessorProblem::SparseTooMany { overrides: n, count });
        }
        let iv = sparse.indices();
        let it = match iv.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isz = component_size(it);
        let ibytes = view_bytes(&iv.view(), buffers)?;
        let indices: Vec<u32> =
            strided(ibytes, iv.offset(), isz, isz, n)?.map(|b| read_index(b, it).unwrap_or(u32::MAX)).collect();
        let vv = sparse.values();
        let vbytes = view_bytes(&vv.view(), buffers)?;
        for (k, e) in strided(vbytes, vv.offset(), elem, elem, n)?.enumerate() {
            let i = indices[k] as usize;
            if i >= count {
                return Err(AccessorProblem::SparseIndex { index: i, count });
            }
            for c in 0..width {
                values[i * width + c] = read_component(&e[c * cs..], t, acc.normalized());
            }
        }
    }
    Ok(Elements { width, values })
}

/// Reads an index accessor (unsigned scalar) as `u32`; errors name the accessor.
pub fn read_indices(acc: &gltf::Accessor<'_>, buffers: &[&[u8]]) -> Result<Vec<u32>, AccessorError> {
    read_indices_inner(acc, buffers).map_err(|problem| AccessorError { accessor: acc.index(), problem })
}

fn read_indices_inner(acc: &gltf::Accessor<'_>, buffers: &[&[u8]]) -> Result<Vec<u32>, AccessorProblem> {
    if acc.dimensions() != Dimensions::Scalar
        || !matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(AccessorProblem::NotUnsignedScalars);
    }
    if acc.sparse().is_some() {
        // Rare for indices: read through the float path, exact here because an accessor holds at most
        // MAX_ELEMENTS (2^24) elements, so a valid index is below 2^24.
        let e = read_floats_inner(acc, buffers)?;
        return Ok(e.values.iter().map(|&v| v as u32).collect());
    }
    let count = acc.count();
    if count > MAX_ELEMENTS {
        return Err(AccessorProblem::TooMany { count, limit: MAX_ELEMENTS });
    }
    let Some(view) = acc.view() else {
        return Ok(vec![0; count]);
    };
    let t = acc.data_type();
    let sz = component_size(t);
    let bytes = view_bytes(&view, buffers)?;
    let stride = view.stride().unwrap_or(sz);
    Ok(strided(bytes, acc.offset(), stride.max(sz), sz, count)?.map(|b| read_index(b, t).unwrap_or(u32::MAX)).collect())
}
