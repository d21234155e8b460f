//! What the expand pass counts (per eye, on the GPU) and the summary a render reports.

use bytemuck::{Pod, Zeroable};

/// One eye's counters as `shaders/expand.wgsl` accumulates them: a `u32` each, indexed by the
/// `STAT_*` constants (which are derived from this layout).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct EyeStats {
    /// Points whose centre has no projection.
    pub culled: u32,
    /// Points that produced a proxy (splatted and hidden ones are counted in `splatted` and
    /// `occluded` alone).
    pub drawn: u32,
    /// Proxies drawn as analytic bounds with forced ray casting.
    pub special: u32,
    /// Proxies drawn a second time across the seam.
    pub seam: u32,
    /// Proxies that did not fit the vertex buffer (a sizing bug when non-zero).
    pub overflow: u32,
    /// Vertices written.
    pub vertices: u32,
    /// Spheres ray cast by the compute splat.
    pub splatted: u32,
    /// Spheres skipped whole, hidden by nearer ones (`shaders/occlusion.wgsl`).
    pub occluded: u32,
    /// Of the splatted spheres, those an ODS pair's splat cast by a workgroup each
    /// (`splat_wide_pair`), counted once for both eyes.
    pub wide: u32,
}

/// Counts from one render, summed over the eyes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RasterStats {
    /// Points whose centre has no projection (inside the viewing circle); ray-cast imposters
    /// still draw them with a conservative proxy, sprites drop them.
    pub culled: u64,
    /// Points that produced a proxy.
    pub drawn: u64,
    /// Proxies drawn as analytic bounds with forced ray casting (eye-enclosing, near the
    /// eye, containing a pole, or a billboard that could not be projected).
    pub special: u64,
    /// Proxies drawn a second time across the seam.
    pub seam_copies: u64,
    /// Proxies ray cast by the compute splat instead of drawn (counted in `drawn` too).
    pub splatted: u64,
    /// Spheres skipped whole because nearer ones hide every pixel they could cover (counted in
    /// `drawn` too: the image is the same as if they were drawn).
    pub occluded: u64,
    /// Vertices written.
    pub vertices: u64,
    /// Of the splatted spheres, those cast by a workgroup each for both eyes of a pair.
    pub wide: u64,
    /// Expand/draw batches submitted (per eye).
    pub batches: u64,
    /// Pieces of a gathered frame skipped unread, hidden whole by the nearer ones drawn before
    /// them in every eye.
    pub hidden_pieces: u64,
    /// Their points, once per eye (not counted in `drawn`).
    pub hidden_points: u64,
}

impl RasterStats {
    /// The sum of `eyes`' counters, with `batches` batches; `Err(n)` when `n` proxies
    /// overflowed the vertex buffer.
    pub(crate) fn sum(eyes: &[EyeStats], batches: u64) -> Result<Self, u64> {
        let total = |f: fn(&EyeStats) -> u32| eyes.iter().map(|e| f(e) as u64).sum::<u64>();
        let overflow = total(|e| e.overflow);
        if overflow > 0 {
            return Err(overflow);
        }
        Ok(RasterStats {
            culled: total(|e| e.culled),
            drawn: total(|e| e.drawn) + total(|e| e.splatted) + total(|e| e.occluded),
            special: total(|e| e.special),
            seam_copies: total(|e| e.seam),
            splatted: total(|e| e.splatted),
            occluded: total(|e| e.occluded),
            vertices: total(|e| e.vertices),
            wide: total(|e| e.wide),
            batches,
            hidden_pieces: 0,
            hidden_points: 0,
        })
    }
}

impl std::fmt::Display for RasterStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} proxies drawn ({} special, {} seam copies, {} splatted, {} hidden by nearer ones, \
             {} cast wide, {} vertices, {} batches), {} points inside the viewing circle, \
             {} pieces ({} points) hidden whole",
            self.drawn,
            self.special,
            self.seam_copies,
            self.splatted,
            self.occluded,
            self.wide,
            self.vertices,
            self.batches,
            self.culled,
            self.hidden_pieces,
            self.hidden_points
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eyes_are_summed_field_by_field_and_overflow_is_an_error() {
        let left = EyeStats {
            culled: 1,
            drawn: 2,
            special: 3,
            seam: 4,
            overflow: 0,
            vertices: 6,
            splatted: 7,
            occluded: 8,
            wide: 9,
        };
        let right = EyeStats {
            culled: 10,
            drawn: 20,
            special: 30,
            seam: 40,
            overflow: 0,
            vertices: 60,
            splatted: 70,
            occluded: 80,
            wide: 90,
        };
        let s = RasterStats::sum(&[left, right], 5).unwrap();
        assert_eq!(
            s,
            RasterStats {
                culled: 11,
                drawn: 22 + 77 + 88,
                special: 33,
                seam_copies: 44,
                splatted: 77,
                occluded: 88,
                vertices: 66,
                wide: 99,
                batches: 5,
                hidden_pieces: 0,
                hidden_points: 0,
            }
        );
        let over = EyeStats {
            overflow: 3,
            ..left
        };
        assert_eq!(RasterStats::sum(&[left, over], 1), Err(3));
    }
}
