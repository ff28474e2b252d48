//! How the raymarcher turns the strands along an eye ray into the hair's opacity
//! (`volume.opacity`).

/// The opacity model of the raymarched volume.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Opacity {
    /// As the strand rasterizer draws them (`"strands"`, the default): every strand met is a line
    /// of the strands' `width_px`, `alpha` and line coverage
    /// ([`tress_shading::line_optical_width`]), as long as its length seen across the ray
    /// ([`tress_shading::strand_optical_depth`]), so a pixel's transmittance falls with the
    /// number of lines drawn over it. A pixel covers more hair farther away, so the surface
    /// comes nearer the outside with distance, as the strands' composite does.
    #[default]
    Strands,
    /// The paper's count (`"iso"`): the transmittance falls as `256^(-strands / iso)`, the solid
    /// surface where `iso` strands were met, whatever the distance.
    Iso,
}

named_setting!(Opacity, "volume.opacity", { Strands => "strands", Iso => "iso" });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_unknown_names_are_errors() {
        for o in [Opacity::Strands, Opacity::Iso] {
            assert_eq!(o.name().parse::<Opacity>().unwrap(), o);
            assert_eq!(o.to_string(), o.name());
        }
        assert_eq!(Opacity::default(), Opacity::Strands);
        let e = "density".parse::<Opacity>().unwrap_err().to_string();
        assert!(e.contains("volume.opacity") && e.contains("density"), "{e}");
    }
}
