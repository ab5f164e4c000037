//! What a driver does in one tick: the only input of the simulation.

/// One tick of driver input, already through deadzones and response curves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Controls {
    /// Steering, -1 (full left) to 1 (full right).
    pub steer: f32,
    /// Throttle, 0 to 1.
    pub throttle: f32,
    /// Brake, 0 to 1.
    pub brake: f32,
}

impl Controls {
    /// The same controls with every value clamped to its range and NaN treated as 0, so a bad input
    /// device or a corrupted trace cannot put NaN into the simulation.
    #[must_use]
    pub fn sanitized(self) -> Self {
        let clean = |v: f32, lo: f32| if v.is_finite() { v.clamp(lo, 1.0) } else { 0.0 };
        Self { steer: clean(self.steer, -1.0), throttle: clean(self.throttle, 0.0), brake: clean(self.brake, 0.0) }
    }
}
