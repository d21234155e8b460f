//! The per-pixel trigonometry of the projections whose longitude depends on the column
//! alone and latitude on the row alone (equirect, full or not, and cylindrical;
//! `shaders/pixel_trig.wgsl`): each column's `(sin lam, cos lam)` and each row's
//! `(sin phi, cos phi, merge(phi))`, computed in f64 as the ray tracer computes its rays and
//! rounded once, so a pixel's ray costs the shaders two loads.

use bytemuck::{Pod, Zeroable};

use crate::projection::pole_merge::PoleMerging;
use crate::projection::{Image, Projection};

use super::shaders;

/// `shaders/pixel_trig.wgsl`.
pub const PIXEL_TRIG: &str = include_str!("../../shaders/pixel_trig.wgsl");

/// One table entry (WGSL `vec4<f32>`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct TrigEntry(pub [f32; 4]);

/// True for the projections the table serves (`is_separable` in the WGSL).
pub fn separable(projection: &Projection) -> bool {
    matches!(
        projection,
        Projection::Equirect { .. } | Projection::Cylindrical { .. }
    )
}

/// The table for `image` under `merging`: `width` columns, then `height` rows. The other
/// projections compute their rays in the shaders and get one unused entry (a binding cannot
/// be empty).
pub fn table(image: &Image, merging: &PoleMerging) -> Vec<TrigEntry> {
    if !separable(&image.projection) {
        return vec![TrigEntry([0.0; 4])];
    }
    // Separable projections show something at every pixel.
    let angles = |i, j| image.pixel_angles(i, j).unwrap_or_default();
    let columns = (0..image.width).map(|i| {
        let (s, c) = angles(i, 0).0.sin_cos();
        TrigEntry([s as f32, c as f32, 0.0, 0.0])
    });
    let rows = (0..image.height).map(|j| {
        let phi = angles(0, j).1;
        let (s, c) = phi.sin_cos();
        TrigEntry([s as f32, c as f32, merging.factor(phi) as f32, 0.0])
    });
    columns.chain(rows).collect()
}

/// Layout of bind group 1 of the expand and imposter pipelines: the table.
pub fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    use wgpu::ShaderStages as S;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("pixel trig"),
        entries: &[shaders::buffer_layout(
            0,
            S::COMPUTE | S::FRAGMENT,
            wgpu::BufferBindingType::Storage { read_only: true },
        )],
    })
}

/// The table uploaded and bound for `layout`.
pub fn bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    table: &[TrigEntry],
) -> wgpu::BindGroup {
    use wgpu::util::DeviceExt;
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("pixel trig"),
        contents: bytemuck::cast_slice(table),
        usage: wgpu::BufferUsages::STORAGE,
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("pixel trig"),
        layout,
        entries: &[shaders::bind(0, &buffer)],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::{PoleMerge, Projection};

    #[test]
    fn entries_are_the_pixel_centres_trigonometry_and_merge() {
        let image = Image::equirect(8);
        let merging = PoleMerging::both(PoleMerge::COMFORTABLE);
        let t = table(&image, &merging);
        assert_eq!(t.len(), 8 + 4);
        // Column 0 is centred at lam = (0.5 / 8 - 0.5) 2 pi; row 0 at phi = (0.5 - 0.5 / 4) pi.
        let lam = (0.5 / 8.0 - 0.5) * std::f64::consts::TAU;
        assert_eq!(t[0].0, [lam.sin() as f32, lam.cos() as f32, 0.0, 0.0]);
        let phi = (0.5 - 0.5 / 4.0) * std::f64::consts::PI;
        let f = merging.factor(phi) as f32;
        assert_eq!(t[8].0, [phi.sin() as f32, phi.cos() as f32, f, 0.0]);
        assert!(f < 1.0, "67.5 degrees is merged");
        // Rows are symmetric about the equator.
        assert_eq!(t[8].0[2], t[11].0[2]);
        assert_eq!(t[8].0[0], -t[11].0[0]);
    }

    #[test]
    fn a_partial_equirect_shares_the_panoramas_entries() {
        // 180 x 90 degrees at 256 wide looks where columns 128.. and rows 64.. of the 512-wide
        // panorama look.
        let full = table(&Image::equirect(512), &PoleMerging::OFF);
        let half = Image::new("equirect:180,90".parse().unwrap(), 256).unwrap();
        let half = table(&half, &PoleMerging::OFF);
        assert_eq!(half.len(), 256 + 128);
        assert_eq!(half[..256], full[128..384]);
        assert_eq!(half[256..], full[512 + 64..512 + 192]);
    }

    #[test]
    fn other_projections_get_one_unused_entry() {
        let image = Image::new(Projection::Hammer, 64).unwrap();
        assert_eq!(table(&image, &PoleMerging::OFF).len(), 1);
    }
}
