//! Helpers the AVX2 loops share: a vector register's worth of values moved between a slice and a register.

/// Loads a `V` (a vector of 4 or 8 lanes) from the start of a slice of its lanes' type (`None` when the slice
/// is shorter).
#[inline(always)]
pub(crate) fn load<T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    let lanes = size_of::<V>() / size_of::<T>();
    Some(bytemuck::pod_read_unaligned(bytemuck::cast_slice(s.get(..lanes)?)))
}

/// Stores a `V` at the start of a slice of its lanes' type (nothing when the slice is shorter).
#[inline(always)]
pub(crate) fn store<T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    let lanes = size_of::<V>() / size_of::<T>();
    if let Some(d) = s.get_mut(..lanes) {
        bytemuck::cast_slice_mut::<T, u8>(d).copy_from_slice(bytemuck::bytes_of(&v));
    }
}
