//! How the volume's shadows and ambient occlusion turn the density volume into strands in the
//! way of a ray (`volume.occlusion`).

/// The occlusion model of volume shadows and ambient occlusion.
///
/// Both march the density volume and raise `1 - alpha` to the number of strands in the way; the
/// model says how the march's samples become that number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Occlusion {
    /// ADSM's model (`"adsm"`, the default), with the strands' `shadow_r`, `shadow_alpha` and
    /// `shadow_bias`. Shadows: the expectation of ADSM's `(1 - alpha)^(r · (d - bias))` over
    /// where the first strand seen from the light lies (module docs). Ambient occlusion: `r`
    /// strands in the way per world unit of the path inside the hair (voxels holding a strand or
    /// more). The volume darkens as the rasterizer's deep shadow maps do, so the two techniques
    /// (and the hybrid's blend between them) agree however dense the hair is.
    #[default]
    Adsm,
    /// The strands counted (`"strands"`): every strand passing through a voxel is in the way
    /// with probability `strand_width / voxel_size`, with the volume's own `shadow_alpha`. Dense
    /// hair shadows more than sparse hair; on short fur it is far lighter than ADSM's default.
    Strands,
}

impl Occlusion {
    /// `VolumeParams.occlusion` (`OCCLUSION_*` in `common/volume.wgsl`).
    pub fn gpu(self) -> u32 {
        match self {
            Occlusion::Strands => 0,
            Occlusion::Adsm => 1,
        }
    }
}

named_setting!(Occlusion, "volume.occlusion", { Adsm => "adsm", Strands => "strands" });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_unknown_names_are_errors() {
        for o in [Occlusion::Adsm, Occlusion::Strands] {
            assert_eq!(o.name().parse::<Occlusion>().unwrap(), o);
        }
        assert_eq!(Occlusion::default(), Occlusion::Adsm);
        let e = "density".parse::<Occlusion>().unwrap_err().to_string();
        assert!(
            e.contains("volume.occlusion") && e.contains("density"),
            "{e}"
        );
        assert_ne!(Occlusion::Adsm.gpu(), Occlusion::Strands.gpu());
    }
}
