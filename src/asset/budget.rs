//! The load budget: named limits on everything one glTF load reads, decodes, builds and places.
//!
//! Why: a glTF file is a small description of possibly enormous work. A few hundred bytes can name a sparse
//! accessor of 16 Mi elements, a hierarchy that places one mesh a million times, or twelve images that all
//! decode the same 8192x8192 picture; a single limit per object does not bound the sum. Every such cost is
//! charged to one [`Meter`] per load as it is incurred (and before the memory is allocated, where the size
//! is known in advance), and the first charge past a limit refuses the file with an [`OverBudget`] that
//! names the limit. The defaults are chosen so that honest big scenes fit: a 1 GiB GLB, a few million
//! polygons after instancing, 128 Mi texels of textures.

use thiserror::Error;

/// Limits on what one load may read, decode, build and place; a file that needs more is refused.
///
/// Each limit is a total over the whole load, and shared things are counted once: a file, `data:` URI,
/// GLB chunk or buffer view named by several buffers or images is read (and decoded) once, and an accessor
/// used by several primitives is read once. Instanced sizes count every placement: a mesh placed 3,000
/// times counts 3,000 times (it is stored once; the renderer transforms it 3,000 times a frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadBudget {
    /// Bytes of the scene file itself (`.gltf` JSON or a whole `.glb`).
    pub file_bytes: u64,
    /// Bytes of all buffers together (external files, decoded `data:` URIs, the GLB binary chunk).
    pub buffer_bytes: u64,
    /// Encoded bytes of all external image files and `data:` image URIs together.
    pub image_bytes: u64,
    /// Decoded texels of all textures together (each costs 4 bytes, and about twice that while decoding).
    pub texels: u64,
    /// Numbers read from accessors (elements times components per element), each accessor read once.
    pub accessor_values: u64,
    /// Vertices after instancing: the vertices of every placed mesh, a LOD set counting its largest model.
    pub vertices: u64,
    /// Polygons after instancing, counted like [`LoadBudget::vertices`].
    pub polygons: u64,
    /// Node visits while walking the scene (a node reached along several paths counts once per path).
    pub node_visits: u64,
    /// Depth of the node hierarchy (deeper is taken as a cycle).
    pub node_depth: u64,
    /// Polygon pairs compared by decal detection over the whole load (see [`super::decals`]); past it the
    /// remaining meshes' decals are not looked for (they draw without a depth bias). Never an error.
    pub decal_pairs: u64,
}

impl Default for LoadBudget {
    fn default() -> Self {
        Self {
            file_bytes: 1 << 30,
            buffer_bytes: 1 << 30,
            image_bytes: 1 << 30,
            texels: 1 << 27,
            accessor_values: 1 << 26,
            vertices: 8 << 20,
            polygons: 4 << 20,
            node_visits: 1 << 20,
            node_depth: 256,
            decal_pairs: 4 << 20,
        }
    }
}

/// One of the limits of a [`LoadBudget`] (except the decal work, which never refuses a file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// [`LoadBudget::file_bytes`].
    FileBytes,
    /// [`LoadBudget::buffer_bytes`].
    BufferBytes,
    /// [`LoadBudget::image_bytes`].
    ImageBytes,
    /// [`LoadBudget::texels`].
    Texels,
    /// [`LoadBudget::accessor_values`].
    AccessorValues,
    /// [`LoadBudget::vertices`].
    Vertices,
    /// [`LoadBudget::polygons`].
    Polygons,
    /// [`LoadBudget::node_visits`].
    NodeVisits,
    /// [`LoadBudget::node_depth`].
    NodeDepth,
}

impl Limit {
    const ALL: [Limit; 9] = [
        Limit::FileBytes,
        Limit::BufferBytes,
        Limit::ImageBytes,
        Limit::Texels,
        Limit::AccessorValues,
        Limit::Vertices,
        Limit::Polygons,
        Limit::NodeVisits,
        Limit::NodeDepth,
    ];

    /// The field's name in [`LoadBudget`].
    #[must_use]
    pub fn field(self) -> &'static str {
        match self {
            Limit::FileBytes => "file_bytes",
            Limit::BufferBytes => "buffer_bytes",
            Limit::ImageBytes => "image_bytes",
            Limit::Texels => "texels",
            Limit::AccessorValues => "accessor_values",
            Limit::Vertices => "vertices",
            Limit::Polygons => "polygons",
            Limit::NodeVisits => "node_visits",
            Limit::NodeDepth => "node_depth",
        }
    }

    /// What the limit counts, in words.
    #[must_use]
    pub fn what(self) -> &'static str {
        match self {
            Limit::FileBytes => "bytes of scene file",
            Limit::BufferBytes => "bytes of buffers",
            Limit::ImageBytes => "bytes of image files",
            Limit::Texels => "decoded texels",
            Limit::AccessorValues => "accessor values",
            Limit::Vertices => "vertices after instancing",
            Limit::Polygons => "polygons after instancing",
            Limit::NodeVisits => "node visits",
            Limit::NodeDepth => "levels of node hierarchy",
        }
    }

    fn of(self, budget: &LoadBudget) -> u64 {
        match self {
            Limit::FileBytes => budget.file_bytes,
            Limit::BufferBytes => budget.buffer_bytes,
            Limit::ImageBytes => budget.image_bytes,
            Limit::Texels => budget.texels,
            Limit::AccessorValues => budget.accessor_values,
            Limit::Vertices => budget.vertices,
            Limit::Polygons => budget.polygons,
            Limit::NodeVisits => budget.node_visits,
            Limit::NodeDepth => budget.node_depth,
        }
    }

    fn slot(self) -> usize {
        self as usize
    }
}

/// A load needs more of something than its budget allows.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
#[error("needs at least {needed} {what}, over the load budget's {allowed} (LoadBudget::{field})", what = limit.what(), field = limit.field())]
pub struct OverBudget {
    /// The limit that was passed.
    pub limit: Limit,
    /// What the load needed when it was refused (a lower bound of what the whole file needs).
    pub needed: u64,
    /// The limit's value.
    pub allowed: u64,
}

/// What one load has used of its budget so far.
#[derive(Clone, Debug)]
pub struct Meter {
    budget: LoadBudget,
    used: [u64; Limit::ALL.len()],
    decal_pairs_left: u64,
}

impl Meter {
    /// A meter with nothing used yet.
    #[must_use]
    pub fn new(budget: LoadBudget) -> Self {
        Self { budget, used: [0; Limit::ALL.len()], decal_pairs_left: budget.decal_pairs }
    }

    /// The budget being metered.
    #[must_use]
    pub fn budget(&self) -> &LoadBudget {
        &self.budget
    }

    /// How much of `limit` has been used.
    #[must_use]
    pub fn used(&self, limit: Limit) -> u64 {
        self.used[limit.slot()]
    }

    /// Whether `amount` more of `limit` would still fit, without charging it.
    pub fn check(&self, limit: Limit, amount: u64) -> Result<(), OverBudget> {
        let needed = self.used(limit).saturating_add(amount);
        let allowed = limit.of(&self.budget);
        if needed > allowed { Err(OverBudget { limit, needed, allowed }) } else { Ok(()) }
    }

    /// Charges `amount` of `limit`, or refuses (charging nothing) when it would pass the limit.
    pub fn charge(&mut self, limit: Limit, amount: u64) -> Result<(), OverBudget> {
        self.check(limit, amount)?;
        self.used[limit.slot()] += amount;
        Ok(())
    }

    /// Checks a level of the hierarchy against [`LoadBudget::node_depth`] (depth is not a running total).
    pub fn check_depth(&self, depth: u64) -> Result<(), OverBudget> {
        let allowed = self.budget.node_depth;
        if depth > allowed { Err(OverBudget { limit: Limit::NodeDepth, needed: depth, allowed }) } else { Ok(()) }
    }

    /// The decal-detection pairs left for the rest of the load; the caller takes what it uses from it.
    pub fn decal_pairs_left(&mut self) -> &mut u64 {
        &mut self.decal_pairs_left
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charges_add_up_and_a_refusal_charges_nothing() {
        let mut m = Meter::new(LoadBudget { texels: 10, ..LoadBudget::default() });
        m.charge(Limit::Texels, 6).unwrap();
        let over = m.charge(Limit::Texels, 5).unwrap_err();
        assert_eq!(over, OverBudget { limit: Limit::Texels, needed: 11, allowed: 10 });
        assert_eq!(m.used(Limit::Texels), 6);
        m.charge(Limit::Texels, 4).unwrap();
        assert!(m.charge(Limit::Texels, u64::MAX).is_err(), "saturates instead of wrapping");
        assert_eq!(
            over.to_string(),
            "needs at least 11 decoded texels, over the load budget's 10 (LoadBudget::texels)"
        );
        assert!(m.check_depth(256).is_ok() && m.check_depth(257).is_err());
    }

    #[test]
    fn every_limit_reads_its_own_field() {
        let b = LoadBudget::default();
        let fields: Vec<u64> = Limit::ALL.iter().map(|l| l.of(&b)).collect();
        assert_eq!(
            fields,
            [b.file_bytes, b.buffer_bytes, b.image_bytes, b.texels, b.accessor_values, b.vertices, b.polygons]
                .into_iter()
                .chain([b.node_visits, b.node_depth])
                .collect::<Vec<_>>()
        );
        for (i, l) in Limit::ALL.iter().enumerate() {
            assert_eq!(l.slot(), i);
        }
    }
}
