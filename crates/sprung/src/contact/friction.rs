//! Coulomb friction between bodies, as impulses after each (sub)step.
//!
//! A penalty force can only approximate friction by a steep function of the
//! sliding speed, which lets a resting body creep downhill (and, steep
//! enough to stop the creep, limits the explicit step). So friction acts on
//! velocities instead, once per (sub)step after the integrator, the way the
//! projection colliders' does. It acts on the touches of the contact
//! force's last evaluation in the (sub)step ([`BodyContacts`]), each with
//! the normal force `f_n` it pushed with: the relative tangential velocity
//! `u_t` of the two closest points, after the step, is reduced by the
//! tangential impulse `J = min(|u_t| / W, μ f_n dt)` along `-u_t`, where `W
//! = Σ wᵢ² / mᵢ` is the pair's inverse effective mass. So each step's
//! friction impulse is at most `μ` times the normal force of the last
//! evaluation times the step: Coulomb's law for the step's normal impulse
//! where the forces are evaluated once a step (Euler, symplectic Euler),
//! its last stage's where they are evaluated several times (RK4, the
//! implicit solvers). Below the friction cone the sliding stops exactly
//! (static friction). A touch that begins within a step gets its first
//! friction in the next. Taking the force's touches rather than measuring
//! the pairs again after the step halves the cost of measuring contacts;
//! every integrator evaluates the forces at least once a step.
//! The impulse is shared by the closest-point weights, opposite on the two
//! sides (the weights sum to zero), so linear momentum is conserved. The
//! positions move by the velocity change times `dt` too, as if the impulse
//! had acted at the start of the (sub)step: otherwise each step's sliding,
//! taken before the friction stops it, would add up to a steady creep of a
//! resting body (`g sin θ dt` per second on a slope). The touches are taken
//! in a fixed order, each seeing the velocities the earlier ones left.
//!
//! **The order, and the threads.** The touches are taken in groups, so
//! that threads can take groups side by side and the result is the same
//! whatever their number. A touch's particles lie in `[lowest, lowest +
//! span]`; with a group width `W` (a power of two, chosen from the
//! touches alone: the least, from [`MIN_GROUP`], with `span < W` for seven
//! touches in eight), a touch with `span < W` is in group `g = ⌊lowest /
//! W⌋` and writes only within `[g W, (g + 2) W)`, so the groups of one
//! parity share no particle. First the even groups, side by side, then
//! the odd ones, each in the touches' order; last, on one thread, the
//! touches with `span ≥ W`, in order. A body's particles are numbered
//! together, so the touches between small neighbouring bodies (a pile of
//! balls) span little; between large ones (two big cloths, a cloth
//! folded on itself) the width grows with their spans, and with fewer
//! groups than threads the threads go idle. With at most
//! [`parallel::CHUNK`] touches, the same passes run on the calling thread
//! alone: the same order, so the same bits, without waking the threads
//! for passes shorter than their waking. The touches with a rigid body's
//! particles are left out of these passes and taken last, on one thread,
//! through the bodies' motions ([`super::rigid_friction`]).
//!
//! [`BodyContacts`]: crate::forces::BodyContacts

use super::pairs::Touch;
use super::rigid_friction;
use super::ImpulseContext;
use crate::parallel;
use crate::units::{Real, Vec3};

/// A count of touches per bit length of their spans (highest particle less
/// lowest): entry `b` counts those spanning `2^(b-1)` to `2^b - 1`
/// particles (entry 0, one particle), the last entry those spanning
/// `2^30` or more.
pub(crate) type Spans = [usize; 32];

/// One touch as the last evaluation pushed it: its normal force, and
/// where its particles lie (what the threads adding its force and its
/// friction choose it by).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pushed {
    /// The normal force (N), not negative.
    pub push: Real,
    /// The touch's lowest particle.
    pub lowest: u32,
    /// Its highest particle less its lowest.
    pub span: u32,
}

/// The narrowest group of particles (a power of two) friction takes
/// touches by: narrower ones would leave the threads too little each.
pub const MIN_GROUP: u64 = 256;

/// The friction stage of the touches of the contact force's last
/// evaluation in the (sub)step ([`BodyContacts`]), with the state and
/// world of `context`: apply friction impulses to the velocities for the
/// touches of `touches` (piece by piece), each with the normal force (N)
/// it pushed with and its particles' extent in `pushed` (piece by piece
/// too), moving the positions by the velocity change times the step;
/// `spans` counts the touches' spans. The touches with particles of the
/// rigid bodies act on their motion, last ([`super::rigid_friction`]),
/// with the buffers of `scratch`.
pub(crate) fn apply_friction(
    (touches, pushed, spans): (&[Vec<Touch>], &[Vec<Pushed>], &Spans),
    context: &mut ImpulseContext,
    scratch: &mut rigid_friction::Scratch,
) {
    let ImpulseContext {
        position,
        velocity,
        inverse_mass,
        contacts,
        rigid,
        dt,
        ..
    } = context;
    let (position, velocity, inverse_mass, dt) =
        (&mut **position, &mut **velocity, *inverse_mass, *dt);
    let friction = contacts.settings.friction;
    if friction == 0.0 || contacts.pairs.is_empty() {
        return;
    }
    let total: usize = spans.iter().sum();
    let mut fewer = 0;
    let mut width = 1_u64 << 32;
    for (bits, count) in spans.iter().enumerate() {
        fewer += count;
        if 1 << bits >= MIN_GROUP && 8 * fewer >= 7 * total {
            width = 1 << bits;
            break;
        }
    }
    let each = |f: &mut dyn FnMut(&Touch, &Pushed)| {
        for (touches, pushed) in touches.iter().zip(pushed) {
            for (touch, pushed) in touches.iter().zip(pushed) {
                f(touch, pushed);
            }
        }
    };
    let slide = |touch: &Touch, push: Real, first: usize, x: &mut [Vec3], v: &mut [Vec3]| {
        slide(touch, push, (first, x, v), inverse_mass, friction, dt);
    };
    let grouped = |span: u32| u64::from(span) < width;
    for parity in [0, 1] {
        let offset = usize::try_from(parity * width).unwrap_or(usize::MAX);
        let align = usize::try_from(2 * width).unwrap_or(usize::MAX);
        let slices = (&mut *position, &mut *velocity);
        let group_pass = |first: usize, (x, v): (&mut [Vec3], &mut [Vec3])| {
            // Whether this pass, on the share `first..end`, takes a
            // touch.
            let end = first + x.len();
            let takes = |touch: &Touch, pushed: &Pushed| {
                let group = u64::from(pushed.lowest) / width;
                grouped(pushed.span)
                    && group % 2 == parity
                    && (first..end).contains(&(pushed.lowest as usize))
                    && !rigid.takes(touch)
            };
            each(&mut |touch, pushed| {
                if takes(touch, pushed) {
                    slide(touch, pushed.push, first, x, v);
                }
            });
        };
        // Few touches: one share on this thread (the same order, so
        // the same bits), rather than waking the threads for a pass
        // shorter than their waking.
        if total <= parallel::CHUNK {
            group_pass(0, slices);
        } else {
            parallel::for_each_aligned_share(slices, align, offset, group_pass);
        }
    }
    let found = &mut scratch.found;
    found.clear();
    each(&mut |touch, pushed| {
        if rigid.takes(touch) {
            if !rigid.within_one(touch) {
                found.push((*touch, pushed.push));
            }
        } else if !grouped(pushed.span) {
            slide(touch, pushed.push, 0, position, velocity);
        }
    });
    rigid.apply_friction(scratch, position, velocity, inverse_mass, friction, dt);
}

/// The friction impulse of one touch, which pushed with `push` (N), on the
/// entries of particles `first..` of positions `x` (m) and velocities `v`
/// (m/s), with friction coefficient `friction` over a (sub)step of `dt`
/// (s).
#[inline(always)]
fn slide(
    touch: &Touch,
    push: Real,
    (first, x, v): (usize, &mut [Vec3], &mut [Vec3]),
    inverse_mass: &[Real],
    friction: Real,
    dt: Real,
) {
    let particle = |i: usize| touch.particles[i] as usize;
    let relative: Vec3 = (0..touch.count)
        .map(|i| touch.weights[i] * v[particle(i) - first])
        .sum();
    let normal_speed = relative.dot(touch.normal);
    let sliding = relative - normal_speed * touch.normal;
    let speed = sliding.length();
    let inverse_effective_mass: Real = (0..touch.count)
        .map(|i| touch.weights[i].powi(2) * inverse_mass[particle(i)])
        .sum();
    if push == 0.0 || speed == 0.0 || inverse_effective_mass == 0.0 {
        return;
    }
    let impulse = (speed / inverse_effective_mass).min(friction * push * dt);
    let along = -impulse / speed * sliding;
    for i in 0..touch.count {
        let change = touch.weights[i] * inverse_mass[particle(i)] * along;
        v[particle(i) - first] += change;
        x[particle(i) - first] += change * dt;
    }
}
