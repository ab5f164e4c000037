//! Per-frame statistics: what happened to the polygons, how many pixels were touched, time per stage.

/// Counts and timings for one rendered frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Mesh instances in the draw list.
    pub objects_in: u64,
    /// Instances skipped whole by bounding-sphere culling.
    pub objects_culled: u64,
    /// Polygons in the draw list (as built, after non-planar ones were split).
    pub polygons_in: u64,
    /// Polygons skipped because their object was culled.
    pub polygons_in_culled_objects: u64,
    /// Polygons wholly outside the view volume.
    pub polygons_outside: u64,
    /// Polygons cut by the near, far or guard-band planes.
    pub polygons_clipped: u64,
    /// Polygons facing away from the camera with a single-sided material.
    pub polygons_backface: u64,
    /// Polygons with zero area on the snapped grid.
    pub polygons_degenerate: u64,
    /// Polygons dropped for NaN or infinite coordinates, or a bad mesh reference.
    pub polygons_invalid: u64,
    /// Polygons that reached the fill stage.
    pub polygons_drawn: u64,
    /// Drawn polygons that were not y-monotone in this view and were split.
    pub polygons_split: u64,
    /// Pieces handed to the scanline fill (a split polygon gives several).
    pub pieces_filled: u64,
    /// LOD-set instances drawn with the close model.
    pub lod_close: u64,
    /// LOD-set instances drawn with the middle model.
    pub lod_mid: u64,
    /// LOD-set instances drawn with the long-shot model.
    pub lod_long: u64,
    /// Polygons not submitted because a coarser model was chosen (against all-close).
    pub polygons_saved_by_lod: u64,
    /// Pixels whose colour was computed.
    ///
    /// None of the three pixel counts counts what the z-buffer's coarse depth skipped
    /// ([`RenderOptions::coarse_depth`](crate::render::RenderOptions::coarse_depth)): polygons hidden whole
    /// by polygons drawn before or after them, and a polygon's pixels in tiles that hide it. With it they
    /// depend on the thread count and on the frames before.
    pub pixels_shaded: u64,
    /// Pixels written to the frame.
    pub pixels_written: u64,
    /// Pixels skipped by the depth test or coverage before shading.
    pub pixels_rejected: u64,
    /// Milliseconds spent culling and transforming vertices.
    pub ms_transform: f64,
    /// Milliseconds spent clipping, projecting, snapping and back-face culling.
    pub ms_clip: f64,
    /// Milliseconds spent ordering (ordering table, sort).
    pub ms_order: f64,
    /// Milliseconds spent filling spans (clearing included).
    pub ms_fill: f64,
}

impl Stats {
    /// Total milliseconds over all stages.
    #[must_use]
    pub fn ms_total(&self) -> f64 {
        self.ms_transform + self.ms_clip + self.ms_order + self.ms_fill
    }
}

/// Milliseconds since `since`, for the stage timings in [`Stats`].
pub(crate) fn ms_since(since: std::time::Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}
