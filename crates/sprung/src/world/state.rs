//! Save and restore what changes from step to step (checkpoints).

use crate::state::{StateError, WorldState};
use crate::units::Real;

use super::World;

impl World {
    /// The state that changes from step to step (see [`crate::state`]):
    /// with the same scene, [`World::restore_state`] gives a world that
    /// steps on with the same bits as this one.
    ///
    /// # Examples
    ///
    /// A run stopped halfway and resumed in a fresh world from the same scene
    /// ends with the same bits as one that never stopped (Verlet's previous
    /// positions are in the state):
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    ///
    /// let scene = || {
    ///     let mut world = World::new(IntegratorKind::Verlet);
    ///     let rope = build::rope(10, 1.0).unwrap().with_stiffness(200.0);
    ///     world.add_body("rope", rope).unwrap();
    ///     world
    /// };
    /// let mut run = scene();
    /// for _ in 0..50 {
    ///     run.step(1e-3).unwrap();
    /// }
    /// let saved = run.save_state();
    /// for _ in 0..50 {
    ///     run.step(1e-3).unwrap();
    /// }
    /// let mut resumed = scene();
    /// resumed.restore_state(&saved).unwrap();
    /// assert_eq!(resumed.steps(), 50);
    /// for _ in 0..50 {
    ///     resumed.step(1e-3).unwrap();
    /// }
    /// assert_eq!(resumed.particles.position, run.particles.position);
    /// assert_eq!(resumed.particles.velocity, run.particles.velocity);
    /// assert_eq!(resumed.time(), run.time());
    /// ```
    pub fn save_state(&self) -> WorldState {
        let mut state = WorldState::default();
        let as_real = |count: u64| count as Real;
        state.put("steps", vec![as_real(self.steps)]);
        state.put("time", vec![self.time, self.time_compensation]);
        state.put_vectors("position", &self.particles.position);
        state.put_vectors("velocity", &self.particles.velocity);
        let muscles = self.muscles.list.iter();
        state.put(
            "muscle.rest_length",
            muscles
                .map(|m| self.springs.rest_length[m.spring])
                .collect(),
        );
        let rotations = self.rigid.list.iter();
        state.put(
            "rigid.rotation",
            rotations.flat_map(|r| r.rotation.to_array()).collect(),
        );
        let stats = |count: u64, first: Option<(u64, Real)>| {
            let (step, error) = first.map_or((0.0, 0.0), |(s, e)| (as_real(s), e));
            vec![as_real(count), step, error]
        };
        let (solver, rods) = (self.solver_stats, self.constraint_stats);
        state.put(
            "solver_stats",
            stats(solver.unconverged_steps, solver.first_unconverged),
        );
        state.put(
            "constraint_stats",
            stats(rods.unconverged_steps, rods.first_unconverged),
        );
        state.integrator = self.integrator.kind().name().to_string();
        self.integrator.save_history(&mut state);
        self.contacts.save_state(&mut state);
        self.save_limits(&mut state);
        state
    }

    /// Put back a state [`World::save_state`] gave, from a world built from
    /// the same scene (the integrator may differ: a different one starts
    /// without history, as after [`World::set_integrator`]). Nothing is changed when the
    /// state is refused (entries missing, of the wrong length, or not finite).
    ///
    /// # Examples
    ///
    /// A state from another scene is refused, and the world left as it was:
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, StateError, World};
    ///
    /// let mut short = World::new(IntegratorKind::Verlet);
    /// short.add_body("rope", build::rope(4, 1.0).unwrap()).unwrap();
    /// let mut long = World::new(IntegratorKind::Verlet);
    /// long.add_body("rope", build::rope(5, 1.0).unwrap()).unwrap();
    /// let error = long.restore_state(&short.save_state()).unwrap_err();
    /// assert!(matches!(error, StateError::Length { expected: 15, found: 12, .. }));
    /// let message = error.to_string();
    /// assert!(message.contains("`position` has 12 numbers where this world needs 15"));
    /// assert_eq!(long.particles.position[4].y, -1.0);
    /// ```
    pub fn restore_state(&mut self, state: &WorldState) -> Result<(), StateError> {
        let n = self.particles.len();
        // The history goes back to the integrator that saved it; another
        // one (switched on the command line) starts afresh.
        let mut integrator = self.integrator.kind().create();
        if state.integrator == self.integrator.kind().name() {
            integrator.restore_history(state, n)?;
        }
        let steps = state.get_count("steps")?;
        let time = state.get("time", 2)?;
        let position = state.get_vectors("position", n)?;
        let velocity = state.get_vectors("velocity", n)?;
        let rest_length = state.get("muscle.rest_length", self.muscles.list.len())?;
        let rotations = state.get("rigid.rotation", 4 * self.rigid.list.len())?;
        let stats = |name: &str| -> Result<(u64, Option<(u64, Real)>), StateError> {
            let values = state.get(name, 3)?;
            let count = |index: usize| {
                let value = values[index];
                (value >= 0.0 && value.fract() == 0.0)
                    .then_some(value as u64)
                    .ok_or_else(|| StateError::BadValue {
                        name: name.to_string(),
                        index,
                        value,
                    })
            };
            let first = count(1)?;
            Ok((count(0)?, (first > 0).then_some((first, values[2]))))
        };
        let (solver, rods) = (stats("solver_stats")?, stats("constraint_stats")?);
        let mut contacts = self.contacts.clone();
        contacts.restore_state(state, &self.bodies, n)?;
        let limits = self.check_limits_state(state)?;
        self.integrator = integrator;
        self.contacts = contacts;
        self.steps = steps;
        (self.time, self.time_compensation) = (time[0], time[1]);
        self.particles.position = position;
        self.particles.velocity = velocity;
        if let Some(limits) = limits {
            self.restore_limits(limits);
        }
        for (muscle, &length) in self.muscles.list.iter().zip(rest_length) {
            self.springs.rest_length[muscle.spring] = length;
        }
        for (body, q) in self.rigid.list.iter_mut().zip(rotations.chunks_exact(4)) {
            body.rotation = glam::DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
        }
        (
            self.solver_stats.unconverged_steps,
            self.solver_stats.first_unconverged,
        ) = solver;
        (
            self.constraint_stats.unconverged_steps,
            self.constraint_stats.first_unconverged,
        ) = rods;
        // The rest lengths came back: the springs' limits bound anew.
        self.limits.refresh(&self.springs, 0..self.springs.len());
        Ok(())
    }
}
