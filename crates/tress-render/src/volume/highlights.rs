//! How the raymarcher shades Kajiya-Kay's specular highlight (`volume.highlights`).

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

named_setting!(Highlights, "volume.highlights", {
    Strands => "strands",
    MeanTangent => "mean_tangent",
});

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
