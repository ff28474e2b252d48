//! [`SatfDatabase`]: the HRIR database in GPU storage buffers, as the online passes read it.

use tress_satf::Database;
use tress_satf::density::DensitySettings;
use wgpu::util::DeviceExt;

use crate::{GpuContext, RenderError};

/// An HRIR database uploaded for the online phase: the features (one `vec4` per sample), and
/// `α̂` and `r̂e` as the file stores them (unorm16, two per `u32`; `[sample][view][pixel]` and
/// `[sample][view][light][pixel]`).
#[derive(Debug)]
pub struct SatfDatabase {
    pub(crate) features: wgpu::Buffer,
    pub(crate) alpha: wgpu::Buffer,
    pub(crate) re: wgpu::Buffer,
    pub(crate) samples: u32,
    pub(crate) view_angles: u32,
    pub(crate) light_angles: u32,
    pub(crate) pixels: u32,
    density: DensitySettings,
    bytes: u64,
}

/// unorm16 values two per word (low half first), padded to a whole word.
fn pack(values: &[u16]) -> Vec<u32> {
    values
        .chunks(2)
        .map(|c| u32::from(c[0]) | (u32::from(c.get(1).copied().unwrap_or(0)) << 16))
        .collect()
}

impl SatfDatabase {
    /// Upload `db`. Fails when an array exceeds the device's storage binding size.
    pub fn new(ctx: &GpuContext, db: &Database) -> Result<Self, RenderError> {
        let h = &db.settings().hrir;
        let features: Vec<[f32; 4]> = db
            .features()
            .iter()
            .map(|f| [f[0], f[1], f[2], 0.0])
            .collect();
        let alpha = pack(db.alpha_raw());
        let re = pack(db.re_raw());
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        for (what, bytes) in [
            ("the HRIR features", features.len() * 16),
            ("the HRIR alpha arrays", alpha.len() * 4),
            ("the HRIR reflectance arrays", re.len() * 4),
        ] {
            if bytes as u64 > limit {
                return Err(RenderError::Limit {
                    what: format!("satf: {what}"),
                    needed: bytes as u64,
                    limit,
                });
            }
        }
        let bytes = (features.len() * 16 + (alpha.len() + re.len()) * 4) as u64;
        let upload = |label: &str, contents: &[u8]| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
        };
        let (features, alpha, re) = ctx.scoped("uploading the HRIR database", || {
            (
                upload("satf/database/features", bytemuck::cast_slice(&features)),
                upload("satf/database/alpha", bytemuck::cast_slice(&alpha)),
                upload("satf/database/re", bytemuck::cast_slice(&re)),
            )
        })?;
        Ok(SatfDatabase {
            features,
            alpha,
            re,
            samples: db.sample_count() as u32,
            view_angles: h.view_angles,
            light_angles: h.light_angles,
            pixels: h.pixels,
            density: db.settings().density,
            bytes,
        })
    }

    /// Samples (generalized sectors).
    pub fn sample_count(&self) -> u32 {
        self.samples
    }

    /// Pixels per HRIR (the maps' texels per sector).
    pub fn pixels(&self) -> u32 {
        self.pixels
    }

    /// The density settings the database was baked with: the online index calculation must
    /// compute sector features with the same ones.
    pub fn density(&self) -> &DensitySettings {
        &self.density
    }

    /// GPU bytes.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unorm16_pairs_low_half_first() {
        assert_eq!(pack(&[1, 2, 0xffff]), vec![0x0002_0001, 0x0000_ffff]);
        assert!(pack(&[]).is_empty());
    }
}
