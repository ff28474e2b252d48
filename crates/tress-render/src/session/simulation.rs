//! Simulated hair in a [`Session`]: every character the strand renderer draws (`strands`,
//! `volume`, `hybrid`, `auto`) simulated on the GPU ([`GpuSimulation`]) and written straight
//! into its vertex buffer, the head moving with it.
//!
//! Each character collides with the triangles of the session's head mesh near its hair (its
//! rest bounds padded by its longest strand), turning about its own pivot (the motion's, else
//! the centre of those triangles, else of its roots). The head mesh's vertices move with the
//! character whose triangles they belong to; the mesh is small, so it is moved on the CPU and
//! uploaded again each frame. `patches` and `satf` draw cards and clusters made from the hair at
//! rest, which do not follow a simulation: simulating while one of them is current is an error.

use std::time::Instant;

use glam::Vec3;
use tress_hair::HairAsset;
use tress_sim::{GuideChoice, MotionSpec, Rigid, SimSettings, Simulation};

use super::{Session, invalid};
use crate::sim::GpuSimulation;
use crate::{GpuContext, RenderError, TriMesh};

/// One simulated character.
#[derive(Debug)]
struct Character {
    gpu: GpuSimulation,
    pivot: Vec3,
    /// The rest hair's bounding sphere, and how far the hair may swing beyond it.
    rest_bounds: (Vec3, f32),
    reach: f32,
}

/// The head mesh at rest and which character each vertex moves with.
#[derive(Debug)]
struct MovingHead {
    rest: TriMesh,
    owner: Vec<Option<usize>>,
}

/// A session's simulation (see the module docs).
#[derive(Debug)]
pub struct SessionSimulation {
    characters: Vec<Character>,
    motion: MotionSpec,
    head: Option<MovingHead>,
    settings: SimSettings,
    time: f64,
}

/// What [`Session::simulate_to`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationFrame {
    /// Steps run by this call (every character).
    pub steps: u64,
    /// Simulated seconds now.
    pub time: f64,
    /// Milliseconds from the first step's recording to the GPU's end of the last (the GPU's
    /// time on a device that runs nothing else), when measured.
    pub wall_ms: Option<f64>,
    /// When measured on a device with timestamp queries: each simulation pass's GPU time
    /// (`sim/integrate`, `sim/grid`, `sim/constraints`, `sim/output`), summed over this call's
    /// substeps and characters; else `NotSupported`.
    pub gpu: crate::Timings,
}

impl SessionSimulation {
    /// The settings.
    pub fn settings(&self) -> &SimSettings {
        &self.settings
    }

    /// The head's motion.
    pub fn motion(&self) -> &MotionSpec {
        &self.motion
    }

    /// Simulated seconds.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The point each character's head turns about (the motion's pivot, else the centre of the
    /// head triangles near its hair, else of its roots), a character each: what an application
    /// driving [`Session::simulate_to_with`] needs to move the head as [`Session::simulate_to`]
    /// would.
    pub fn pivots(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.characters.iter().map(|c| c.pivot)
    }

    /// Guides and strands simulated (all characters).
    pub fn counts(&self) -> (usize, usize) {
        self.characters.iter().fold((0, 0), |(g, s), c| {
            let (guides, followers) = c.gpu.simulation().counts();
            (g + guides, s + guides + followers)
        })
    }

    /// GPU memory of every character's simulation.
    pub fn bytes(&self) -> u64 {
        self.characters.iter().map(|c| c.gpu.bytes()).sum()
    }

    /// The simulations, a character each.
    pub fn characters(&self) -> impl Iterator<Item = &GpuSimulation> {
        self.characters.iter().map(|c| &c.gpu)
    }
}

/// The strands to simulate of a character made by `follow` (each guide first, then its
/// `count` followers), or a share of them.
fn guide_choice(
    scene: &tress_scene::Scene,
    index: usize,
    settings: &SimSettings,
    asset: &HairAsset,
) -> GuideChoice {
    let spec = scene.hair.get(index);
    let whole = spec.is_none_or(|h| h.strand_ratio >= 1.0);
    match spec.and_then(|h| h.follow.as_ref()) {
        Some(f) if whole && f.count > 0 => {
            let stride = f.count as usize + 1;
            GuideChoice::Strands(
                (0..asset.strand_count())
                    .step_by(stride)
                    .map(|s| s as u32)
                    .collect(),
            )
        }
        _ => GuideChoice::Share(settings.guides),
    }
}

/// The triangles of `mesh` whose bounds meet `lo`–`hi`, as a mesh, and the mesh's vertices they
/// use.
fn triangles_near(mesh: &TriMesh, lo: Vec3, hi: Vec3) -> (TriMesh, Vec<usize>) {
    let mut out = TriMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
    };
    let mut used = Vec::new();
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    for t in mesh.indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
        let (tlo, thi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
        if thi.cmplt(lo).any() || tlo.cmpgt(hi).any() {
            continue;
        }
        for &v in t {
            let v = v as usize;
            if remap[v] == u32::MAX {
                remap[v] = out.positions.len() as u32;
                out.positions.push(mesh.positions[v]);
                out.normals
                    .push(mesh.normals.get(v).copied().unwrap_or(Vec3::Y));
                used.push(v);
            }
            out.indices.push(remap[v]);
        }
    }
    (out, used)
}

impl Session {
    /// Start simulating every character with `settings`, the head moving as `motion` says
    /// (time 0 now). The current technique must draw strands.
    pub fn start_simulation(
        &mut self,
        ctx: &GpuContext,
        settings: SimSettings,
        motion: MotionSpec,
    ) -> Result<(), RenderError> {
        settings.validate().map_err(|e| invalid(e.to_string()))?;
        motion.validate().map_err(|e| invalid(e.to_string()))?;
        self.check_simulated_technique()?;
        self.prepare(ctx)?;
        if self.prepared.objects.is_empty() {
            return Err(invalid("the scene has no hair to simulate"));
        }
        let head_mesh = self.prepared.head.clone();
        let mut owner = vec![None; head_mesh.as_ref().map_or(0, |m| m.positions.len())];
        let mut characters = Vec::with_capacity(self.prepared.objects.len());
        for (k, object) in self.prepared.objects.iter().enumerate() {
            let asset = &object.asset;
            let b = asset.bounds();
            let reach = asset.strand_lengths().into_iter().fold(0.0f32, f32::max);
            let (lo, hi) = (b.min - Vec3::splat(reach), b.max + Vec3::splat(reach));
            let near = head_mesh.as_ref().map(|m| triangles_near(m, lo, hi));
            if let Some((_, used)) = &near {
                for &v in used {
                    owner[v].get_or_insert(k);
                }
            }
            let collider = near
                .as_ref()
                .map(|(m, _)| m)
                .filter(|m| !m.indices.is_empty());
            let pivot = motion.pivot.unwrap_or_else(|| match collider {
                Some(m) => {
                    let (c, _) = m.bounding_sphere();
                    c
                }
                None => {
                    let roots: Vec<Vec3> = (0..asset.strand_count())
                        .map(|s| asset.positions()[asset.strand_range(s).start])
                        .collect();
                    roots.iter().copied().sum::<Vec3>() / roots.len().max(1) as f32
                }
            });
            let guides = guide_choice(&self.scene, k, &settings, asset);
            let sim = Simulation::new(asset, collider, &settings, &guides, motion.at(0.0, pivot))
                .map_err(|e| invalid(e.to_string()))?;
            characters.push(Character {
                gpu: GpuSimulation::new(ctx, sim)?,
                pivot,
                rest_bounds: (b.center(), b.size().length() * 0.5),
                reach,
            });
        }
        self.simulation = Some(SessionSimulation {
            characters,
            head: head_mesh.map(|rest| MovingHead { rest, owner }),
            motion,
            settings,
            time: 0.0,
        });
        // The state at time 0: the head where the motion starts.
        self.simulate_to(ctx, 0.0, false)?;
        Ok(())
    }

    fn check_simulated_technique(&self) -> Result<(), RenderError> {
        if !self.technique.draws_strands() {
            return Err(invalid(format!(
                "simulated hair is drawn by the strands, volume, hybrid and auto techniques, not `{}` \
                 (patches and satf draw cards and clusters made from the hair at rest)",
                self.technique
            )));
        }
        Ok(())
    }

    /// Every character's vertex positions as the frames draw them (read back from the GPU, in
    /// the characters' order): the simulated hair, for a cache or a test.
    pub fn read_hair_positions(&mut self, ctx: &GpuContext) -> Result<Vec<Vec3>, RenderError> {
        self.prepare(ctx)?;
        let strands = self
            .strands
            .as_ref()
            .ok_or_else(|| invalid("the strand renderer is not prepared"))?;
        let mut out = Vec::new();
        for geometry in &strands.hair {
            let bytes = crate::gpu::read_whole_buffer(
                ctx,
                geometry.vertex_buffer(),
                "session/hair-positions/readback",
            )?;
            let vertices: &[crate::gpu::types::StrandVertex] = bytemuck::cast_slice(&bytes);
            out.extend(
                vertices
                    .iter()
                    .take(geometry.vertex_count() as usize)
                    .map(|v| Vec3::from_array(v.position)),
            );
        }
        Ok(out)
    }

    /// The simulation, when one runs.
    pub fn simulation(&self) -> Option<&SessionSimulation> {
        self.simulation.as_ref()
    }

    /// Stop simulating: the hair and the head go back to rest.
    pub fn stop_simulation(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let Some(sim) = self.simulation.take() else {
            return Ok(());
        };
        if let (Some(head), Some(geometry)) = (&sim.head, &mut self.head) {
            geometry.update_mesh(ctx, &head.rest)?;
        }
        if let Some(s) = self.strands.as_mut() {
            for (geometry, object) in s.hair.iter_mut().zip(&self.prepared.objects) {
                geometry.update_positions(ctx, &object.asset)?;
            }
        }
        Ok(())
    }

    /// Run the steps due by `t` seconds of simulated time and write the hair into the frames'
    /// vertex buffers (no readback); the head moves to where the motion has it at the last step.
    /// With `measure`, waits for the GPU and reports the wall time.
    pub fn simulate_to(
        &mut self,
        ctx: &GpuContext,
        t: f64,
        measure: bool,
    ) -> Result<SimulationFrame, RenderError> {
        let (motion, pivots) = match &self.simulation {
            Some(sim) => (
                sim.motion.clone(),
                sim.characters.iter().map(|c| c.pivot).collect::<Vec<_>>(),
            ),
            None => return Err(invalid("no simulation runs (start one first)")),
        };
        self.simulate_to_with(ctx, t, measure, |k, time| motion.at(time, pivots[k]))
    }

    /// [`Session::simulate_to`] with the application's own head: `head(character, time)` is
    /// where character `character`'s head is at `time` seconds (a rigid transform of the space
    /// its hair and head mesh were given in), asked for at the end of every step. An embedding
    /// application drives the simulation this way from its own animation.
    pub fn simulate_to_with(
        &mut self,
        ctx: &GpuContext,
        t: f64,
        measure: bool,
        head: impl Fn(usize, f32) -> Rigid,
    ) -> Result<SimulationFrame, RenderError> {
        self.check_simulated_technique()?;
        self.prepare(ctx)?;
        let sim = self
            .simulation
            .as_mut()
            .ok_or_else(|| invalid("no simulation runs (start one first)"))?;
        let strands = self
            .strands
            .as_mut()
            .ok_or_else(|| invalid("the strand renderer is not prepared"))?;
        let start = Instant::now();
        let mut steps = 0;
        let mut gpu = crate::Timings::NotSupported;
        for (k, (c, geometry)) in sim
            .characters
            .iter_mut()
            .zip(strands.hair.iter_mut())
            .enumerate()
        {
            c.gpu.set_timing(ctx, measure);
            steps += c.gpu.advance_to(ctx, t, |time| head(k, time))?;
            c.gpu.write_positions(ctx, geometry)?;
            gpu = sum_timings(gpu, c.gpu.take_timings());
            let head = c.gpu.simulation().head();
            geometry.bounds = (head.apply(c.rest_bounds.0), c.rest_bounds.1 + 0.5 * c.reach);
        }
        if let (Some(moving), Some(geometry)) = (&sim.head, &mut self.head) {
            let heads: Vec<Rigid> = sim
                .characters
                .iter()
                .map(|c| c.gpu.simulation().head())
                .collect();
            let mut mesh = moving.rest.clone();
            for (v, owner) in moving.owner.iter().enumerate() {
                if let Some(k) = owner {
                    mesh.positions[v] = heads[*k].apply(moving.rest.positions[v]);
                    if let Some(n) = mesh.normals.get_mut(v) {
                        *n = heads[*k].turn(*n);
                    }
                }
            }
            geometry.update_mesh(ctx, &mesh)?;
        }
        let wall_ms = if measure {
            ctx.device.poll(wgpu::PollType::wait_indefinitely())?;
            Some(start.elapsed().as_secs_f64() * 1e3)
        } else {
            None
        };
        sim.time = t;
        Ok(SimulationFrame {
            steps,
            time: t,
            wall_ms,
            gpu,
        })
    }
}

/// Two characters' pass times added pass by pass (`NotSupported` is none yet).
fn sum_timings(a: crate::Timings, b: crate::Timings) -> crate::Timings {
    use crate::Timings::{NotSupported, Passes};
    match (a, b) {
        (NotSupported, b) => b,
        (a, NotSupported) => a,
        (Passes(mut a), Passes(b)) => {
            for p in b {
                match a.iter_mut().find(|q| q.name == p.name) {
                    Some(q) => q.ms += p.ms,
                    None => a.push(p),
                }
            }
            Passes(a)
        }
    }
}
