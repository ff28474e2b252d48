//! The GPU memory breakdown of a frame.

/// Bytes of GPU memory a technique holds, by kind (logical sizes: what was allocated, before
/// any driver padding).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Memory {
    /// Vertex, index and strand buffers, with the head mesh.
    pub geometry: u64,
    /// The strand rasterizer's OIT: PPLL nodes and heads, or ShortCut's layers and
    /// transmittance (whichever drew the frame).
    pub oit: u64,
    /// Voxel counters, the density/tangent volume and occupancy blocks.
    pub volumes: u64,
    /// Shadow maps.
    pub shadow_maps: u64,
    /// Textures: the patch textures, the SATF map atlas.
    pub textures: u64,
    /// The SATF HRIR database.
    pub database: u64,
}

impl Memory {
    /// The kinds with their names, in a fixed order (CSV columns, tables).
    pub fn rows(&self) -> [(&'static str, u64); 6] {
        [
            ("geometry", self.geometry),
            ("oit", self.oit),
            ("volumes", self.volumes),
            ("shadow_maps", self.shadow_maps),
            ("textures", self.textures),
            ("database", self.database),
        ]
    }

    /// All kinds together.
    pub fn total(&self) -> u64 {
        self.rows().iter().map(|r| r.1).sum()
    }
}

impl std::fmt::Display for Memory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mib = |b: u64| b as f64 / f64::from(1 << 20);
        write!(f, "{:.1} MiB (", mib(self.total()))?;
        let mut first = true;
        for (name, bytes) in self.rows().iter().filter(|r| r.1 > 0) {
            if !first {
                write!(f, ", ")?;
            }
            first = false;
            write!(f, "{name} {:.1}", mib(*bytes))?;
        }
        write!(f, ")")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn total_is_the_sum_of_the_rows_and_display_skips_zero_rows() {
        let m = Memory {
            geometry: 3 << 20,
            oit: 1 << 20,
            database: 2 << 20,
            ..Memory::default()
        };
        assert_eq!(m.total(), 6 << 20);
        assert_eq!(
            m.to_string(),
            "6.0 MiB (geometry 3.0, oit 1.0, database 2.0)"
        );
    }
}
