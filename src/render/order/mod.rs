//! Visibility ordering: the drawing order of the frame's polygons for the painter's methods.
//!
//! [`ordering_table`] is seed 000's depth-bucket table (Sega): keys spread over buckets between the nearest
//! and farthest key of the frame, chained far to near or near to far. [`view_lists`] is seed 004's orders
//! made in advance per view direction (Canon), whose objects are then placed with the table. `sort` is an
//! exact stable sort by key. The z-buffer needs no order: it draws in submission order.

pub mod ordering_table;
pub mod view_lists;

use self::ordering_table::{Direction, OrderingTable};
use crate::render::core::options::{Method, RenderOptions};

/// The drawing order of the last frame and the table that made it, kept from frame to frame.
#[derive(Debug, Default)]
pub(crate) struct Order {
    /// Polygon indices (into the main batch) in drawing order; empty for the z-buffer.
    pub(crate) order: Vec<u32>,
    table: OrderingTable,
    used_table: bool,
}

impl Order {
    /// Orders polygons `0..keys.len()` by their keys (larger is farther) for `options.method`.
    pub(crate) fn run(&mut self, keys: &[f32], options: &RenderOptions) {
        self.order.clear();
        self.used_table = matches!(options.method, Method::BucketFar | Method::BucketNear | Method::ViewLists);
        match options.method {
            Method::ZBuffer => {}
            Method::Sort => {
                self.order.extend(0..keys.len() as u32);
                // Stable: polygons with equal keys keep submission order. Far (large key) first.
                self.order.sort_by(|&a, &b| {
                    let key = |i: u32| keys.get(i as usize).copied().unwrap_or(0.0);
                    key(b).total_cmp(&key(a))
                });
            }
            Method::BucketFar | Method::BucketNear | Method::ViewLists => {
                // The table spans the frame's finite keys, so its buckets are spent where polygons are.
                let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
                for &k in keys.iter().filter(|k| k.is_finite()) {
                    near = near.min(k);
                    far = far.max(k);
                }
                let direction =
                    if options.method == Method::BucketNear { Direction::NearToFar } else { Direction::FarToNear };
                self.table.reset(options.buckets, options.mapping, near, far, direction);
                // The order the linked buckets would give (on one thread: see `OrderingTable::sort`).
                self.table.sort(keys, &mut self.order);
            }
        }
    }

    /// How many polygons each bucket held in the last frame (nearest first); empty when the last frame did
    /// not use the table.
    pub(crate) fn occupancy(&self) -> Vec<u32> {
        if self.used_table { self.table.occupancy() } else { Vec::new() }
    }
}
