//! How the raymarcher shades Kajiya-Kay's specular highlight (`volume.highlights`).

use std::fmt;
use std::str::FromStr;

use crate::RenderError;

/// Where the volume's Kajiya-Kay highlights come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Highlights {
    /// The strands' own (`"strands"`, the default): the voxelizer sums every strand sample's
    /// specular term for this frame's view and lights per voxel, and the raymarcher shades with
    /// each light's mean ([`tress_shading::highlights`]). The mean of the strands' narrow lobes
    /// puts the highlights where the rasterized strands have them. Costs a second `rgba8` texture
    /// (4 bytes a voxel) and two more counter words a voxel. Kajiya-Kay shading only.
    #[default]
    Strands,
    /// The paper's (`"mean_tangent"`): the lobe of the voxels' mean tangent, widened by their
    /// spread (Toksvig).
    MeanTangent,
}

impl Highlights {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Highlights::Strands => "strands",
            Highlights::MeanTangent => "mean_tangent",
        }
    }
}

impl FromStr for Highlights {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "strands" => Ok(Highlights::Strands),
            "mean_tangent" => Ok(Highlights::MeanTangent),
            _ => Err(RenderError::Invalid(format!(
                "unknown volume.highlights `{s}` (expected strands or mean_tangent)"
            ))),
        }
    }
}

impl fmt::Display for Highlights {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_unknown_names_are_errors() {
        for h in [Highlights::Strands, Highlights::MeanTangent] {
            assert_eq!(h.name().parse::<Highlights>().unwrap(), h);
            assert_eq!(h.to_string(), h.name());
        }
        assert_eq!(Highlights::default(), Highlights::Strands);
        let e = "mean".parse::<Highlights>().unwrap_err().to_string();
        assert!(e.contains("volume.highlights") && e.contains("mean"), "{e}");
    }
}
