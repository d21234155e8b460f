//! What a pipeline is compiled for: the mode fields of [`Params`], fixed through the
//! pipeline-overridable constants of `shaders/params.wgsl`, so the driver folds the other
//! modes' code away. On llvmpipe a fragment pays for every branch it could take, and the
//! full equirect ran at a third of its speed once the shaders carried every projection, eye
//! model and the depth map.

use super::constants::{PROJ_EQUIRECT_FULL, SPEC_MONO, SPEC_STEREO};
use super::params::Params;
use crate::render::RenderSettings;

/// The modes one pipeline serves (WGSL `SPEC_*` overrides).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Specialisation {
    /// A `PROJ_*` constant.
    pub projection: u32,
    /// `SPEC_MONO` or `SPEC_STEREO`.
    pub eyes: u32,
    /// A `MODEL_*` constant.
    pub model: u32,
    /// An `OFFSET_*` constant.
    pub offset: u32,
    /// 1 with a depth map, else 0.
    pub depth_map: u32,
    /// A `PROXY_*` constant.
    pub proxy: u32,
    /// An `IMPOSTER_*` constant.
    pub imposter: u32,
    /// A shading mode of `shaders/shading.wgsl`.
    pub shading: u32,
}

impl Specialisation {
    /// The modes `params` draws in.
    pub fn of(params: &Params) -> Self {
        Specialisation {
            projection: params.projection,
            eyes: if params.eye_sign == 0.0 {
                SPEC_MONO
            } else {
                SPEC_STEREO
            },
            model: params.eye_model,
            offset: params.ods_offset,
            depth_map: u32::from(params.depth_map_count > 0),
            proxy: params.proxy,
            imposter: params.imposter,
            shading: params.shading,
        }
    }

    /// The modes the views of a frame under `settings` (its drawn settings: cube-map stereo's
    /// faces) are drawn in: every view alike, the eyes differing only in sign.
    pub fn of_frame(settings: &RenderSettings) -> Self {
        let views = settings.views();
        Specialisation::of(&Params::new(&views[0], settings, 0, (0, 0), 0))
    }

    /// Whether the keyed path splats both eyes in one dispatch (`expand_splat_pair`): stereo
    /// in the full equirect, whose eyes differ only in their sign.
    pub fn splats_pairs(&self) -> bool {
        self.eyes == SPEC_STEREO && self.projection == PROJ_EQUIRECT_FULL
    }

    /// The pipeline constants, by their WGSL names.
    pub fn constants(&self) -> [(&'static str, f64); 8] {
        [
            ("SPEC_PROJECTION", self.projection.into()),
            ("SPEC_EYES", self.eyes.into()),
            ("SPEC_MODEL", self.model.into()),
            ("SPEC_OFFSET", self.offset.into()),
            ("SPEC_DEPTH_MAP", self.depth_map.into()),
            ("SPEC_PROXY", self.proxy.into()),
            ("SPEC_IMPOSTER", self.imposter.into()),
            ("SPEC_SHADING", self.shading.into()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::super::shaders::{PARAMS, compose};
    use super::*;

    #[test]
    fn every_constant_is_an_override_of_the_params_shader() {
        let source = compose(&[PARAMS]);
        let module = wgpu::naga::front::wgsl::parse_str(&source).expect("WGSL parses");
        let overrides: Vec<String> = module
            .overrides
            .iter()
            .filter_map(|(_, o)| o.name.clone())
            .collect();
        let spec = Specialisation::of(&bytemuck::Zeroable::zeroed());
        let names: Vec<String> = spec.constants().iter().map(|c| c.0.to_string()).collect();
        assert_eq!(overrides, names);
    }
}
