//! [`SimBuffers`]: every buffer of a [`super::GpuSimulation`], uploaded from the CPU twin.

use glam::Vec3;
use tress_sim::{SimSettings, Simulation, Substep};
use wgpu::util::DeviceExt;

use super::{UNIFORM_SLOTS, UNIFORM_STRIDE};
use crate::gpu::types::{
    RigidGpu, SimFollower, SimFollowerVertex, SimOutputParams, SimParams, SimRest,
};
use crate::{GpuContext, RenderError};

/// The simulation's buffers.
#[derive(Debug)]
pub(crate) struct SimBuffers {
    /// Substep uniforms, [`UNIFORM_SLOTS`] slots [`UNIFORM_STRIDE`] apart.
    pub(crate) uniforms: wgpu::Buffer,
    /// The three position buffers (vec4 a vertex), taking turns.
    pub(crate) positions: [wgpu::Buffer; 3],
    pub(crate) rest: wgpu::Buffer,
    pub(crate) offsets: wgpu::Buffer,
    /// 4 i32 a node.
    pub(crate) grid: wgpu::Buffer,
    pub(crate) sdf: wgpu::Buffer,
    pub(crate) shapes: wgpu::Buffer,
    pub(crate) output_uniform: wgpu::Buffer,
    pub(crate) frames: wgpu::Buffer,
    pub(crate) guide_first: wgpu::Buffer,
    pub(crate) followers: wgpu::Buffer,
    pub(crate) follower_vertex_data: wgpu::Buffer,
    /// Rest length of the segment ending at each follower vertex.
    pub(crate) follower_len: wgpu::Buffer,
    /// Number of followers.
    pub(crate) followers_count: u32,
    pub(crate) guide_vertices: u32,
    pub(crate) guides: u32,
    pub(crate) follower_vertices: u32,
    pub(crate) asset_vertices: usize,
    pub(crate) grid_nodes: u32,
    /// What does not change between substeps.
    fixed: SimParams,
    /// Bytes of GPU memory.
    pub(crate) bytes: u64,
}

fn vec4s(v: &[Vec3]) -> Vec<[f32; 4]> {
    v.iter().map(|p| p.extend(0.0).to_array()).collect()
}

/// A storage buffer with `contents`, padded to at least 16 bytes (bindings cannot be empty).
fn storage(
    ctx: &GpuContext,
    label: &str,
    contents: &[u8],
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut bytes = contents.to_vec();
    if bytes.len() < 16 {
        bytes.resize(16, 0);
    }
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE | extra,
        })
}

impl SimBuffers {
    pub(crate) fn new(ctx: &GpuContext, sim: &Simulation) -> Result<Self, RenderError> {
        let l = sim.layout();
        let s = sim.settings();
        let n = l.rest.len();
        let guides = l.offsets.len() - 1;
        let mut rest = Vec::with_capacity(n);
        for g in 0..guides {
            for i in l.offsets[g] as usize..l.offsets[g + 1] as usize {
                rest.push(SimRest {
                    position: l.rest[i].to_array(),
                    rest_len: l.rest_len[i],
                    global_w: l.global_w[i],
                    margin: l.margin[i],
                    flags: u32::from(i == l.offsets[g] as usize),
                    strand: g as u32,
                });
            }
        }
        let followers: Vec<SimFollower> = (0..l.bindings.len())
            .map(|f| {
                let b = &l.bindings[f];
                SimFollower {
                    guides: [
                        b.guides[0],
                        b.guides[1],
                        b.guides[2],
                        l.follower_offsets[f + 1] - l.follower_offsets[f],
                    ],
                    weights: [b.weights[0], b.weights[1], b.weights[2], 0.0],
                    first: l.follower_offsets[f],
                    asset_first: l.follower_first[f],
                    _pad0: 0,
                    _pad1: 0,
                }
            })
            .collect();
        let mut follower_vertices = Vec::with_capacity(l.follower_rest.len());
        for f in 0..l.bindings.len() {
            for i in l.follower_offsets[f] as usize..l.follower_offsets[f + 1] as usize {
                follower_vertices.push(SimFollowerVertex {
                    offset: l.follower_rest[i].to_array(),
                    follower: f as u32,
                });
            }
        }
        let grid = l.grid;
        let nodes = (grid.dims.x * grid.dims.y * grid.dims.z) as usize;
        let colliders = sim.colliders();
        let mut shapes: Vec<[f32; 4]> = Vec::new();
        for sp in &colliders.spheres {
            shapes.push(sp.center.extend(sp.radius).to_array());
            shapes.push([0.0; 4]);
        }
        for c in &colliders.capsules {
            shapes.push(c.a.extend(c.radius).to_array());
            shapes.push(c.b.extend(1.0).to_array());
        }
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        let check = |what: &str, bytes: usize| {
            if bytes as u64 > limit {
                Err(RenderError::Limit {
                    what: what.into(),
                    needed: bytes as u64,
                    limit,
                })
            } else {
                Ok(())
            }
        };
        check("simulation follower vertices", follower_vertices.len() * 16)?;
        check("simulation positions", n * 16)?;
        let cpy = wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        let none = wgpu::BufferUsages::empty();
        let positions = [
            storage(
                ctx,
                "sim/state/positions-0",
                bytemuck::cast_slice(&vec4s(l.x_prev)),
                cpy,
            ),
            storage(
                ctx,
                "sim/state/positions-1",
                bytemuck::cast_slice(&vec4s(l.x)),
                cpy,
            ),
            storage(
                ctx,
                "sim/state/positions-2",
                bytemuck::cast_slice(&vec4s(l.x)),
                cpy,
            ),
        ];
        let uniforms = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sim/step/uniforms"),
            size: UNIFORM_STRIDE * UNIFORM_SLOTS as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let output_uniform = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sim/output/uniform"),
            size: std::mem::size_of::<SimOutputParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (sdf_values, sdf_origin, sdf_dims) = match &colliders.sdf {
            Some(f) => (
                f.values.clone(),
                f.origin.extend(f.cell).to_array(),
                [f.dims.x, f.dims.y, f.dims.z, 1],
            ),
            None => (vec![0.0], [0.0, 0.0, 0.0, 1.0], [1, 1, 1, 0]),
        };
        let decay = (-s.damping * s.substep_dt()).exp();
        let fixed = SimParams {
            gravity: s.gravity.extend(s.substep_dt()).to_array(),
            wind_dir: s
                .wind
                .direction
                .normalize_or_zero()
                .extend(s.wind.strength)
                .to_array(),
            wind: [s.wind.turbulence, s.wind.drag, 0.0, decay],
            shape: [
                s.per_iteration(s.local_stiffness),
                s.per_iteration(s.global_stiffness),
                0.0,
                s.hair_friction,
            ],
            grid_params: [s.hair_volume, grid.rest_peak, s.friction, 0.0],
            grid_origin: grid.origin.extend(grid.cell).to_array(),
            grid_dims: [grid.dims.x, grid.dims.y, grid.dims.z, 0],
            sdf_origin,
            sdf_dims,
            counts: [
                n as u32,
                guides as u32,
                s.iterations,
                colliders.spheres.len() as u32,
            ],
            counts2: [
                colliders.capsules.len() as u32,
                follower_vertices.len() as u32,
                u32::from(s.hair_friction > 0.0 || s.hair_volume > 0.0),
                0,
            ],
            ..SimParams::default()
        };
        let mut grid_zero = vec![0i32; 4 * nodes];
        grid_zero.truncate(4 * nodes);
        let this = SimBuffers {
            uniforms,
            rest: storage(ctx, "sim/state/rest", bytemuck::cast_slice(&rest), none),
            offsets: storage(
                ctx,
                "sim/state/offsets",
                bytemuck::cast_slice(l.offsets),
                none,
            ),
            grid: storage(ctx, "sim/grid/sums", bytemuck::cast_slice(&grid_zero), none),
            sdf: storage(
                ctx,
                "sim/colliders/sdf",
                bytemuck::cast_slice(&sdf_values),
                none,
            ),
            shapes: storage(
                ctx,
                "sim/colliders/shapes",
                bytemuck::cast_slice(&shapes),
                none,
            ),
            output_uniform,
            frames: storage(ctx, "sim/output/frames", &vec![0u8; 16 * n], none),
            guide_first: storage(
                ctx,
                "sim/output/guide-first",
                bytemuck::cast_slice(&l.guide_first),
                none,
            ),
            followers: storage(
                ctx,
                "sim/output/followers",
                bytemuck::cast_slice(&followers),
                none,
            ),
            follower_vertex_data: storage(
                ctx,
                "sim/output/follower-vertices",
                bytemuck::cast_slice(&follower_vertices),
                none,
            ),
            follower_len: storage(
                ctx,
                "sim/output/follower-lengths",
                bytemuck::cast_slice(l.follower_len),
                none,
            ),
            followers_count: followers.len() as u32,
            positions,
            guide_vertices: n as u32,
            guides: guides as u32,
            follower_vertices: follower_vertices.len() as u32,
            asset_vertices: n + follower_vertices.len(),
            grid_nodes: nodes as u32,
            fixed,
            bytes: 0,
        };
        let bytes = [
            &this.positions[0],
            &this.positions[1],
            &this.positions[2],
            &this.rest,
            &this.offsets,
            &this.grid,
            &this.sdf,
            &this.shapes,
            &this.frames,
            &this.guide_first,
            &this.followers,
            &this.follower_vertex_data,
            &this.follower_len,
            &this.uniforms,
        ]
        .iter()
        .map(|b| b.size())
        .sum();
        Ok(SimBuffers { bytes, ..this })
    }

    /// The uniforms of `sub` (what changes each substep over what does not).
    pub(crate) fn params(&self, s: &SimSettings, sub: &Substep) -> SimParams {
        let mut p = self.fixed;
        p.h0 = RigidGpu::from(sub.h0);
        p.h1 = RigidGpu::from(sub.h1);
        p.delta = RigidGpu::from(sub.delta);
        p.wind[2] = sub.time;
        p.shape[2] = sub.shock;
        let _ = s;
        p
    }

    /// Read (previous, current) positions back at `phase` (blocking).
    pub(crate) fn read_state(
        &self,
        ctx: &GpuContext,
        phase: usize,
    ) -> Result<(Vec<Vec3>, Vec<Vec3>), RenderError> {
        let read = |b: &wgpu::Buffer| -> Result<Vec<Vec3>, RenderError> {
            let bytes = crate::gpu::read_whole_buffer(ctx, b, "sim/state/readback")?;
            Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
                .iter()
                .take(self.guide_vertices as usize)
                .map(|v| Vec3::new(v[0], v[1], v[2]))
                .collect())
        };
        Ok((
            read(&self.positions[phase % 3])?,
            read(&self.positions[(phase + 1) % 3])?,
        ))
    }

    /// Write (previous, current) positions at `phase`.
    pub(crate) fn write_state(
        &self,
        ctx: &GpuContext,
        phase: usize,
        prev: &[[f32; 4]],
        cur: &[[f32; 4]],
    ) {
        ctx.queue
            .write_buffer(&self.positions[phase % 3], 0, bytemuck::cast_slice(prev));
        ctx.queue.write_buffer(
            &self.positions[(phase + 1) % 3],
            0,
            bytemuck::cast_slice(cur),
        );
        ctx.queue.submit([]);
    }
}
