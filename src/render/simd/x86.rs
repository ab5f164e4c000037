//! Helpers the AVX2 loops share: a vector register's worth of values moved between a slice and a register.
//!
//! Each copies a fixed-size array (`[T; N]`, the register's lanes) and casts it, which compiles to one
//! unaligned vector load or store once the slice's length has been checked.

/// Loads a `V` of `N` lanes from the start of a slice of its lanes' type (`None` when the slice is shorter).
#[inline(always)]
fn load_lanes<const N: usize, T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    let a: &[T; N] = s.get(..N)?.try_into().ok()?;
    Some(bytemuck::cast::<[T; N], V>(*a))
}

/// Stores a `V` of `N` lanes at the start of a slice of its lanes' type (nothing when the slice is shorter).
#[inline(always)]
fn store_lanes<const N: usize, T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    if let Some(d) = s.get_mut(..N) {
        d.copy_from_slice(&bytemuck::cast::<V, [T; N]>(v));
    }
}

/// Loads four 32-bit lanes (an SSE register, as the narrow small-triangle fill uses).
#[inline(always)]
pub(crate) fn load4<T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    load_lanes::<4, T, V>(s)
}

/// Stores four 32-bit lanes.
#[inline(always)]
pub(crate) fn store4<T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    store_lanes::<4, T, V>(s, v);
}

/// Stores eight 32-bit lanes (an AVX register, as the span chunks use).
#[inline(always)]
pub(crate) fn store8<T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    store_lanes::<8, T, V>(s, v);
}

/// Loads eight 32-bit lanes.
#[inline(always)]
pub(crate) fn load8<T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    load_lanes::<8, T, V>(s)
}
