//! A converged reference: traced until two independent renders agree.
//!
//! A fixed sample count says nothing about how close a reference is to its limit: 64 samples
//! leave the hair's speckle and fireflies, which any comparison against it then scores. Here two
//! renders with different seeds (`A`, `B`) start at the tracer's `spp`; while their matched-scale
//! FLIP over the mask ([`crate::matched`], the **floor**) is above the threshold, each gets as
//! many new samples again (a render with a fresh seed at the current count, averaged in with
//! equal weight, so the count doubles without discarding work) until the floor is below the
//! threshold or the count reaches `max_spp`. The reference is `A`; `B` is its seed-pair twin,
//! whose distance from `A` is the noise floor reported with every score.

use crate::{Image, TraceError, Tracer, matched};

/// When a reference counts as converged.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergeSettings {
    /// The seed pair's matched-scale FLIP over the mask must fall to or below this.
    pub threshold: f64,
    /// The matched scale's box factor.
    pub scale: u32,
    /// The most samples a pixel gets (the count doubles from the tracer's `spp` up to here).
    pub max_spp: u32,
}

impl Default for ConvergeSettings {
    fn default() -> Self {
        ConvergeSettings {
            threshold: 0.01,
            scale: matched::DEFAULT_SCALE,
            max_spp: 1024,
        }
    }
}

/// A reference traced to convergence.
#[derive(Clone, Debug)]
pub struct Converged {
    /// The reference (`A`).
    pub image: Image,
    /// Its twin with other seeds (`B`).
    pub second: Image,
    /// Samples per pixel of each.
    pub spp: u32,
    /// The seed pair's matched-scale FLIP over the mask at `spp`.
    pub floor: f64,
    /// Whether the floor reached the threshold (false: stopped at `max_spp`).
    pub converged: bool,
    /// `(spp, floor)` after every round, the last one is this result's.
    pub history: Vec<(u32, f64)>,
}

/// Trace `tracer`'s scene until converged (see the module docs). `mask` (the frame's size)
/// selects the pixels the floor is measured over, e.g. the hair's; `None` is the whole frame.
/// `round(spp, floor)` is called after each round (for progress). The tracer's seed and `spp`
/// are changed; the first round uses its settings' seed and the next one.
pub fn render_converged(
    tracer: &mut Tracer,
    mask: Option<&[bool]>,
    settings: &ConvergeSettings,
    round: &dyn Fn(u32, f64),
) -> Result<Converged, TraceError> {
    if !(settings.threshold.is_finite() && settings.threshold >= 0.0) {
        return Err(TraceError::Invalid(format!(
            "the convergence threshold must be a non-negative number, got {}",
            settings.threshold
        )));
    }
    let start_spp = tracer.settings().spp;
    if settings.max_spp < start_spp {
        return Err(TraceError::Invalid(format!(
            "the most samples a pixel ({}) is below the first round's ({start_spp})",
            settings.max_spp
        )));
    }
    let mut seed = tracer.settings().seed;
    let mut next = |tracer: &mut Tracer| {
        tracer.set_seed(seed);
        seed = seed.wrapping_add(1);
        tracer.render(&|_| {}).image
    };
    let mut a = next(tracer);
    let mut b = next(tracer);
    let mut spp = start_spp;
    let mut history = Vec::new();
    loop {
        let floor = matched::compare(&a, &b, mask, settings.scale)?;
        let floor = floor.flip_masked.unwrap_or(floor.flip);
        history.push((spp, floor));
        round(spp, floor);
        let converged = floor <= settings.threshold;
        if converged || spp.saturating_mul(2) > settings.max_spp {
            return Ok(Converged {
                image: a,
                second: b,
                spp,
                floor,
                converged,
                history,
            });
        }
        // As many new samples again: equal weights keep each pixel an unweighted mean.
        tracer.set_spp(spp)?;
        let more_a = next(tracer);
        let more_b = next(tracer);
        average_into(&mut a, &more_a);
        average_into(&mut b, &more_b);
        spp *= 2;
    }
}

fn average_into(into: &mut Image, other: &Image) {
    for (p, q) in into.pixels.iter_mut().zip(&other.pixels) {
        *p = (*p + *q) * 0.5;
    }
}
