//! The world's side of tearing: adding a join, the give
//! stage, the surfaces that open along broken springs, and what of it a
//! saved state holds.

use std::collections::HashSet;

use crate::error::{BuildError, ENERGY_LIMIT};
use crate::state::{StateError, WorldState};
use crate::surface;
use crate::tearing::StrainLimits;
use crate::tearing::{Join, JoinData, JoinEnd, JoinLink};
use crate::units::Real;

use super::World;

impl World {
    /// Check `data` and add it as a join between two bodies already in the
    /// world (or two particles of one body); returns the join's index.
    /// Nothing is added when the join is refused.
    ///
    /// A rope tied to a ball: the rope's last particle joined to the
    /// ball's first by a stiff spring that breaks past 50 % strain.
    ///
    /// ```
    /// use sprung::build::{self, SurfaceSprings};
    /// use sprung::{IntegratorKind, JoinData, JoinEnd, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.add_body("rope", build::rope(5, 1.0).unwrap().with_stiffness(500.0)).unwrap();
    /// let ball = build::icosphere(0.1, 1, SurfaceSprings::default()).unwrap();
    /// let ball = ball.placed(1.0, Vec3::ZERO, Vec3::new(0.0, -1.2, 0.0));
    /// world.add_body("ball", ball.with_stiffness(500.0)).unwrap();
    /// let mut join = JoinData::between(JoinEnd::new("rope", 4), JoinEnd::new("ball", 0));
    /// join.stiffness = 1e3;
    /// join.break_strain = Some(0.5);
    /// assert_eq!(world.add_join(join.clone()), Ok(0));
    /// join.b.particle = 1000;
    /// let error = world.add_join(join).unwrap_err();
    /// assert!(error.to_string().starts_with("join `b` = [\"ball\", 1000]: particle index out of range"));
    /// ```
    pub fn add_join(&mut self, data: JoinData) -> Result<usize, BuildError> {
        data.validate()?;
        let a = self.join_particle(&data.a, "a")?;
        let b = self.join_particle(&data.b, "b")?;
        if a == b {
            return Err(BuildError::BadJoin("`a` and `b` are the same particle"));
        }
        let x = &self.particles.position;
        let rest = data
            .rest_length
            .unwrap_or_else(|| x[a as usize].distance(x[b as usize]));
        if !(rest.is_finite() && rest > 0.0) {
            return Err(BuildError::BadJoin(
                "its ends are at the same place: give it a positive `rest_length`",
            ));
        }
        // A join longer than the world is wide cannot hold within it.
        let reach = 2.0 * self.settings.max_distance;
        if rest > reach {
            return Err(BuildError::BeyondLimit {
                field: "rest_length",
                index: self.joins.len(),
                value: rest,
                limit: reach,
            });
        }
        let link = if data.rod {
            if self.particles.is_pinned(a as usize) && self.particles.is_pinned(b as usize) {
                return Err(BuildError::BadJoin(
                    "a rod (`rod = true`) between two pinned particles moves nothing: it needs a free end",
                ));
            }
            self.rods.push(a, b, rest);
            JoinLink::Rod(self.rods.len() - 1)
        } else {
            let energy = 0.5 * data.stiffness * reach * reach;
            if energy.is_nan() || energy >= ENERGY_LIMIT {
                return Err(BuildError::EnergyOverflow {
                    field: "stiffness",
                    index: self.joins.len(),
                    value: data.stiffness,
                    energy,
                });
            }
            let s = self.springs.len();
            self.springs
                .push(a, b, rest, data.stiffness, data.damping, false);
            let limits = StrainLimits {
                break_strain: data.break_strain,
                ..StrainLimits::default()
            };
            self.limits.set(&self.springs, s..s + 1, limits);
            JoinLink::Spring(s)
        };
        self.joins.push(Join {
            data,
            particles: [a, b],
            link,
        });
        Ok(self.joins.len() - 1)
    }

    /// The world index of a join's end `end` (`a` or `b`).
    fn join_particle(&self, end: &JoinEnd, name: &'static str) -> Result<u32, BuildError> {
        let body = self
            .body(&end.body)
            .ok_or_else(|| BuildError::JoinUnknownBody {
                end: name,
                body: end.body.clone(),
            })?;
        if end.particle >= body.particles.len() {
            return Err(BuildError::JoinParticleOutOfRange {
                end: name,
                body: end.body.clone(),
                particle: end.particle,
                particles: body.particles.len(),
            });
        }
        Ok((body.particles.start + end.particle) as u32)
    }

    /// Whether join `j` has broken.
    pub fn join_broken(&self, j: usize) -> bool {
        match self.joins[j].link {
            JoinLink::Spring(s) => self.springs.is_broken(s),
            JoinLink::Rod(_) => false,
        }
    }

    /// The springs that are joins, in spring order, and the rods that are.
    pub fn join_links(&self) -> (HashSet<usize>, HashSet<usize>) {
        let mut springs = HashSet::new();
        let mut rods = HashSet::new();
        for join in &self.joins {
            match join.link {
                JoinLink::Spring(s) => springs.insert(s),
                JoinLink::Rod(r) => rods.insert(r),
            };
        }
        (springs, rods)
    }

    /// The give stage: springs past their limits yield or break
    /// ([`crate::tearing`]); the faces and segments along broken springs
    /// open. Nothing to do (one branch) where no spring has a limit.
    pub(crate) fn give(&mut self) {
        if !self.limits.enabled() {
            return;
        }
        // The muscles moved their springs' rest lengths (those that can
        // give are bounded anew, and searched for every step).
        for muscle in &self.muscles.list {
            let s = muscle.spring;
            if self.limits.can_give(s) {
                self.limits.refresh(&self.springs, s..s + 1);
            }
        }
        let given = self
            .limits
            .give(&mut self.springs, &self.particles.position);
        if !given.broken.is_empty() {
            self.open_surfaces(&given.broken);
        }
    }

    /// Open every body's faces and segments along the broken springs
    /// `broken`: a face with a broken spring along an edge goes, and a body
    /// that loses one is no longer closed (its gas escapes: no pressure
    /// from then on, and the gas's energy `−nRT ln V` joins the work the
    /// springs took out, so the balance closes across the burst).
    fn open_surfaces(&mut self, broken: &[usize]) {
        let (position, time) = (&self.particles.position, self.time());
        for body in &mut self.bodies {
            let cut: HashSet<(u32, u32)> = broken
                .iter()
                .filter(|s| body.springs.contains(s))
                .map(|&s| {
                    let [a, b] = self.springs.endpoints(s);
                    (a.min(b), a.max(b))
                })
                .collect();
            if cut.is_empty() {
                continue;
            }
            let crosses = |a: u32, b: u32| cut.contains(&(a.min(b), a.max(b)));
            // The gas's energy −nRT ln V, from the closed surface's volume
            // before it opens: it leaves with the gas.
            let gas_energy = match (&body.gas, body.closed) {
                (Some(gas), true) => {
                    let volume = body.gas_volume(gas.volume_model, position);
                    (volume > 0.0).then(|| -gas.nrt_at(time) * volume.ln())
                }
                _ => None,
            };
            let (faces, segments) = (body.faces.len(), body.segments.len());
            body.faces
                .retain(|&[i, j, k]| !(crosses(i, j) || crosses(j, k) || crosses(k, i)));
            body.segments.retain(|&[i, j]| !crosses(i, j));
            if body.faces.len() != faces || body.segments.len() != segments {
                let wide: Vec<[usize; 3]> =
                    body.faces.iter().map(|f| f.map(|i| i as usize)).collect();
                body.edges = surface::unique_edges(&wide)
                    .into_iter()
                    .map(|e| e.map(|i| i as u32))
                    .collect();
                if let Some(energy) = gas_energy {
                    self.limits.add_work(energy);
                }
                body.closed = false;
            }
        }
    }

    /// Put what the springs' limits did into `state`: the broken springs,
    /// every rest length and yield strain, the count and the work.
    pub(crate) fn save_limits(&self, state: &mut WorldState) {
        if !self.limits.enabled() {
            return;
        }
        let broken = (0..self.springs.len()).filter(|&s| self.springs.is_broken(s));
        state.put("limits.broken", broken.map(|s| s as Real).collect());
        state.put("limits.rest_length", self.springs.rest_length.clone());
        // A state holds finite numbers: -1 stands for "never yields".
        let yields = self.limits.yield_strains().iter();
        let yields = yields.map(|&y| if y.is_finite() { y } else { -1.0 });
        state.put("limits.yield_strain", yields.collect());
        let totals = vec![
            self.limits.broken_count() as Real,
            self.limits.plastic_work(),
        ];
        state.put("limits.totals", totals);
    }

    /// What [`World::save_limits`] put into `state`, checked: the broken
    /// springs, rest lengths, yield strains and totals. A spring broken
    /// in this world but whole in the state is refused (a broken spring
    /// cannot be mended).
    pub(crate) fn check_limits_state(
        &self,
        state: &WorldState,
    ) -> Result<Option<LimitsState>, StateError> {
        if !self.limits.enabled() {
            return Ok(None);
        }
        let bad = |name: &str, index: usize, value: Real| StateError::BadValue {
            name: name.to_string(),
            index,
            value,
        };
        let broken: Vec<usize> = state
            .get_any("limits.broken")?
            .iter()
            .enumerate()
            .map(|(index, &value)| {
                let whole =
                    value >= 0.0 && value.fract() == 0.0 && value < self.springs.len() as Real;
                whole
                    .then_some(value as usize)
                    .ok_or_else(|| bad("limits.broken", index, value))
            })
            .collect::<Result<_, _>>()?;
        let mut in_state = vec![false; self.springs.len()];
        broken.iter().for_each(|&s| in_state[s] = true);
        if let Some(s) =
            (0..self.springs.len()).find(|&s| self.springs.is_broken(s) && !in_state[s])
        {
            return Err(bad(
                "limits.broken (a spring broken here is whole there)",
                s,
                s as Real,
            ));
        }
        let rest_length = state
            .get("limits.rest_length", self.springs.len())?
            .to_vec();
        if let Some(index) = rest_length
            .iter()
            .position(|&l| !(l.is_finite() && l > 0.0))
        {
            return Err(bad("limits.rest_length", index, rest_length[index]));
        }
        let yield_strain = state
            .get("limits.yield_strain", self.limits.yield_strains().len())?
            .iter()
            .enumerate()
            .map(|(index, &y)| match y {
                -1.0 => Ok(Real::INFINITY),
                y if y > 0.0 => Ok(y),
                y => Err(bad("limits.yield_strain", index, y)),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let totals = state.get("limits.totals", 2)?;
        if !(totals[0] >= 0.0 && totals[0].fract() == 0.0) {
            return Err(bad("limits.totals", 0, totals[0]));
        }
        Ok(Some(LimitsState {
            broken,
            rest_length,
            yield_strain,
            totals: (totals[0] as u64, totals[1]),
        }))
    }

    /// Put a checked [`LimitsState`] back: break its springs (opening the
    /// surfaces along them), set the rest lengths, yield strains, totals.
    pub(crate) fn restore_limits(&mut self, saved: LimitsState) {
        let newly: Vec<usize> = saved
            .broken
            .into_iter()
            .filter(|&s| !self.springs.is_broken(s))
            .collect();
        newly.iter().for_each(|&s| self.springs.break_spring(s));
        if !newly.is_empty() {
            self.open_surfaces(&newly);
        }
        self.springs.rest_length = saved.rest_length;
        self.limits.restore_yield_strains(&saved.yield_strain);
        self.limits.restore_totals(saved.totals.0, saved.totals.1);
    }
}

/// The springs' limits as a saved state holds them, checked.
#[derive(Debug)]
pub(crate) struct LimitsState {
    broken: Vec<usize>,
    rest_length: Vec<Real>,
    yield_strain: Vec<Real>,
    totals: (u64, Real),
}
