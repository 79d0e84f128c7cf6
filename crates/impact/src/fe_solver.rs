//! Ball + Simo beam + contact law, coupled monolithically and integrated by HHT-alpha.
//!
//! **Model.** The beam (`simo-beam`) lies along x from the first support, its thickness along
//! z; the ball is a rigid sphere of mass m with three translational unknowns, starting at first
//! touch above the top face at the impact point and moving along -z. Gravity acts on the ball
//! only (the beam's own sag is the reference state, as in the modal method).
//!
//! **Contact.** Frictionless, node-to-segment style: for the ball centre c the contact element
//! is the element whose chord (x_a, x_b) passes nearest to c; on it the contact point is the
//! projection `xi = (c - x_a).t / t.t`, `x = x_a + xi t`, the face normal is the interpolated
//! section axis `n = normalise((1 - xi) d3_a + xi d3_b)` (d3 = Lambda E3, so it turns with the
//! sections) and the approach is
//!
//! `delta = R + h/2 - (c - x).n`
//!
//! (positive in compression; the struck face is half the thickness h from the centre line).
//! The contact force F = law(delta, delta-dot) does the virtual work `-F d(delta)`: its
//! generalised force is `F grad(delta)` over the 15 unknowns it touches (ball, and the
//! displacements and rotation increments of both nodes), and its Newton matrix is
//! `k grad grad^T + F Hess(delta)` (+ the damping term `c grad grad^T` times dv/dq), where
//! gradient and Hessian come from second-order forward differentiation (num-dual) of the
//! formula above, so the geometric terms of the sliding contact point and turning normal are
//! all in it. (The Hessian is taken for `Lambda exp(theta^)` with one increment; composing two
//! increments adds a skew term of size F |c - x| |theta|^2 that vanishes when the ball sits
//! on the normal: Newton stays quadratic in practice.)
//!
//! **Events.** Contact onset and separation are located in time by re-stepping from the last
//! state before the event with a step found by the Illinois method on `delta(tau) = release`,
//! so a contact starts and ends on its own instant, not on the step grid. In contact the step
//! starts at the plan's contact step and adapts to the ball's local error estimate (see
//! [`CONTACT_ERROR`]); out of contact the step grows to `solver.time_step` while the gap and
//! closing speed allow (a step never jumps past a predicted touch).
//!
//! **Contact element.** The element found at the last accepted step is kept while the ball
//! projects on it (within [`STICKY_REACH`] past its ends), so a ball over a node does not switch
//! elements between Newton iterations.

use crate::error::ImpactError;
use crate::history::{History, Sample};
use crate::illinois::Illinois;
use crate::modal_solver::{refined_max, Outcome};
use crate::plan::{FeTarget, Law, Plan};
use crate::report::{static_stiffness, Contact, Ending, Energy, Report};
use crate::scene::SupportName;
use faer::{Col, ColMut, ColRef};
use hertz::ContactLaw;
use hht::{Integrator, Model, NewtonOptions, NewtonWeights, Scheme, State, Triplets};
use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};
use simo_beam::{BeamModel, BeamState, Mesh, Section, Support};

/// Configuration of the coupled model: the beam's and the ball centre's (m).
#[derive(Debug, Clone)]
pub struct Config {
    /// The beam.
    pub beam: BeamState,
    /// Ball centre (m).
    pub ball: Vector3<f64>,
}

/// How many derivatives of the approach to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Order {
    Value,
    Gradient,
    Hessian,
}

/// Unknowns of one contact element: ball (3), node a (6), node b (6).
const LOCAL: usize = 15;

/// The contact kinematics at a configuration: which element, where, and delta with its
/// gradient and Hessian over the element's 15 local unknowns.
#[derive(Debug, Clone)]
struct ContactPoint {
    element: usize,
    xi: f64,
    delta: f64,
    gradient: SVector<f64, LOCAL>,
    hessian: SMatrix<f64, LOCAL, LOCAL>,
}

/// The coupled ball-beam-contact model for [`hht`].
pub struct BallOnBeam<'a, L: ContactLaw> {
    beam: BeamModel,
    nb: usize,
    mass: f64,
    gravity: f64,
    radius: f64,
    half_thickness: f64,
    law: &'a L,
    /// The law's history, committed after every accepted step.
    pub law_state: L::State,
    /// Global equation numbers of each element's 15 local unknowns.
    local_dofs: Vec<[Option<usize>; LOCAL]>,
    /// The contact element of the last accepted step, kept while the projection stays on it
    /// (see [`BallOnBeam::nearest_element`]).
    sticky_element: Option<usize>,
}

/// How far past its ends (in element lengths) the projection may fall on the sticky element
/// before the nearest element is searched again. Without it a ball over a node flips between
/// the two elements from one Newton iteration to the next (equal approach, different
/// derivatives): Newton then oscillated with the residual's sign and halved the step.
pub const STICKY_REACH: f64 = 0.05;

/// Local position error of the ball allowed per contact step, as a fraction of the largest
/// approach on a rigid support. A Hertzian pulse then keeps about the plan's contact step;
/// the heavy ball's chattering contacts (1 kg, 5 m/s at 0.8 L, first 2 ms) move by < 0.2 %
/// in peak force from the fixed-step result, where 1e-6 moved them by 10 % and 1e-5 by 25 %.
pub const CONTACT_ERROR: f64 = 1e-8;

/// delta = R + h/2 - (c - x).n for local unknowns `u` = (ball displacement, node a
/// displacement and rotation increment, node b likewise) about the configuration given.
#[allow(clippy::too_many_arguments)]
fn approach_of<T: nalgebra::RealField + Copy>(
    u: &SVector<T, LOCAL>,
    c0: &Vector3<f64>,
    xa0: &Vector3<f64>,
    xb0: &Vector3<f64>,
    ra: &UnitQuaternion<f64>,
    rb: &UnitQuaternion<f64>,
    reach: f64,
) -> T {
    let lift = |v: &Vector3<f64>| v.map(nalgebra::convert::<f64, T>);
    let part = |k: usize| Vector3::new(u[k], u[k + 1], u[k + 2]);
    let c = lift(c0) + part(0);
    let xa = lift(xa0) + part(3);
    let xb = lift(xb0) + part(9);
    // d3 = Lambda exp(theta^) E3 to second order in theta (all a Hessian at theta = 0 needs).
    let d3 = |r: &UnitQuaternion<f64>, th: Vector3<T>| {
        let e3 = Vector3::new(T::zero(), T::zero(), T::one());
        let turned =
            e3 + th.cross(&e3) + th.cross(&th.cross(&e3)) * nalgebra::convert::<f64, T>(0.5);
        let m = r.to_rotation_matrix().into_inner().map(nalgebra::convert::<f64, T>);
        m * turned
    };
    let da = d3(ra, part(6));
    let db = d3(rb, part(12));
    let t = xb - xa;
    let xi = (c - xa).dot(&t) / t.dot(&t);
    let x = xa + t * xi;
    let d = da * (T::one() - xi) + db * xi;
    let n = d / d.norm();
    nalgebra::convert::<f64, T>(reach) - (c - x).dot(&n)
}

impl<'a, L: ContactLaw> BallOnBeam<'a, L> {
    /// The coupled model: `beam`, a ball of `mass` (kg) and `radius` (m) under `gravity`
    /// (m/s^2, along -z), a struck face `half_thickness` (m) above the centre line, and `law`.
    pub fn new(
        beam: BeamModel,
        mass: f64,
        gravity: f64,
        radius: f64,
        half_thickness: f64,
        law: &'a L,
    ) -> Self {
        let nb = beam.ndof();
        let local_dofs = beam
            .mesh()
            .elements
            .iter()
            .map(|e| {
                let mut d = [None; LOCAL];
                for (k, slot) in d.iter_mut().take(3).enumerate() {
                    *slot = Some(nb + k);
                }
                for (end, node) in e.nodes.iter().enumerate() {
                    for k in 0..6 {
                        d[3 + 6 * end + k] = beam.dof(*node, k);
                    }
                }
                d
            })
            .collect();
        Self {
            beam,
            nb,
            mass,
            gravity,
            radius,
            half_thickness,
            law,
            law_state: L::State::default(),
            local_dofs,
            sticky_element: None,
        }
    }

    /// The beam model.
    pub fn beam(&self) -> &BeamModel {
        &self.beam
    }

    /// Keeps the contact element of configuration `q` (an accepted step) for the next steps.
    pub fn commit_contact_element(&mut self, q: &Config) {
        self.sticky_element = Some(self.nearest_element(q).0);
    }

    /// The contact element and the clamped projection on it: the sticky element while the
    /// ball centre projects within [`STICKY_REACH`] of it, otherwise the element whose chord
    /// passes nearest to the ball centre.
    fn nearest_element(&self, q: &Config) -> (usize, f64) {
        if let Some(i) = self.sticky_element {
            let e = &self.beam.mesh().elements[i];
            let (xa, xb) = (q.beam.positions[e.nodes[0]], q.beam.positions[e.nodes[1]]);
            let t = xb - xa;
            let xi = (q.ball - xa).dot(&t) / t.dot(&t);
            if (-STICKY_REACH..=1.0 + STICKY_REACH).contains(&xi) {
                return (i, xi.clamp(0.0, 1.0));
            }
        }
        let mut best = (0, 0.0, f64::INFINITY);
        for (i, e) in self.beam.mesh().elements.iter().enumerate() {
            let (xa, xb) = (q.beam.positions[e.nodes[0]], q.beam.positions[e.nodes[1]]);
            let t = xb - xa;
            let xi = ((q.ball - xa).dot(&t) / t.dot(&t)).clamp(0.0, 1.0);
            let distance = (q.ball - (xa + t * xi)).norm();
            if distance < best.2 {
                best = (i, xi, distance);
            }
        }
        (best.0, best.1)
    }

    /// Approach only (no derivatives), for event location and the history.
    fn approach(&self, q: &Config) -> f64 {
        self.contact_point(q, Order::Value).delta
    }

    /// The contact point with derivatives up to `order` (the others left zero): the residual
    /// needs the gradient, only the Newton matrix in contact needs the Hessian.
    fn contact_point(&self, q: &Config, order: Order) -> ContactPoint {
        let (element, xi) = self.nearest_element(q);
        let e = &self.beam.mesh().elements[element];
        let (a, b) = (e.nodes[0], e.nodes[1]);
        let reach = self.radius + self.half_thickness;
        let (c, xa, xb) = (&q.ball, &q.beam.positions[a], &q.beam.positions[b]);
        let (ra, rb) = (&q.beam.rotations[a], &q.beam.rotations[b]);
        let zero = SVector::<f64, LOCAL>::zeros();
        let (delta, gradient, hessian) = match order {
            Order::Value => {
                (approach_of(&zero, c, xa, xb, ra, rb, reach), SVector::zeros(), SMatrix::zeros())
            }
            Order::Gradient => {
                let (d, g) = num_dual::gradient(
                    |u: SVector<DualSVec64<LOCAL>, LOCAL>| {
                        approach_of(&u, c, xa, xb, ra, rb, reach)
                    },
                    &zero,
                );
                (d, g, SMatrix::zeros())
            }
            Order::Hessian => num_dual::hessian(
                |u: SVector<Dual2SVec64<LOCAL>, LOCAL>| approach_of(&u, c, xa, xb, ra, rb, reach),
                &zero,
            ),
        };
        ContactPoint { element, xi, delta, gradient, hessian }
    }

    /// The contact point with the gradient if the ball touches (`None` otherwise).
    fn touching(&self, q: &Config, order: Order) -> Option<ContactPoint> {
        let p = self.contact_point(q, Order::Value);
        (p.delta > self.law.release_approach(&self.law_state)).then(|| self.contact_point(q, order))
    }

    /// delta-dot = grad(delta) . local velocities.
    fn rate(&self, p: &ContactPoint, v: ColRef<'_, f64>) -> f64 {
        self.local_dofs[p.element]
            .iter()
            .zip(p.gradient.iter())
            .map(|(d, g)| d.map_or(0.0, |i| g * v[i]))
            .sum()
    }

    /// Contact approach, its rate and the law's force at a state.
    fn contact(&self, q: &Config, v: ColRef<'_, f64>) -> (f64, f64, hertz::ContactForce) {
        let p = self.contact_point(q, Order::Gradient);
        let rate = self.rate(&p, v);
        (p.delta, rate, self.law.force(&self.law_state, p.delta, rate))
    }

    fn ball(&self, x: ColRef<'_, f64>) -> Vector3<f64> {
        Vector3::new(x[self.nb], x[self.nb + 1], x[self.nb + 2])
    }
}

impl<L: ContactLaw> Model for BallOnBeam<'_, L> {
    type Config = Config;

    fn ndof(&self) -> usize {
        self.nb + 3
    }

    fn update(&self, q: &mut Config, dq: ColRef<'_, f64>) {
        self.beam.update(&mut q.beam, dq.subrows(0, self.nb));
        q.ball += self.ball(dq);
    }

    fn inertial_force(
        &self,
        q: &Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
        let nb = self.nb;
        self.beam.inertial_force(
            &q.beam,
            v.subrows(0, nb),
            a.subrows(0, nb),
            out.as_mut().subrows_mut(0, nb),
        );
        for k in 0..3 {
            out[nb + k] = self.mass * a[nb + k];
        }
    }

    fn net_force(&self, t: f64, q: &Config, v: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
        let nb = self.nb;
        self.beam.net_force(t, &q.beam, v.subrows(0, nb), out.as_mut().subrows_mut(0, nb));
        // Gravity pulls the ball along -z: net force = -(external) = +m g e_z.
        out[nb] = 0.0;
        out[nb + 1] = 0.0;
        out[nb + 2] = self.mass * self.gravity;
        let Some(p) = self.touching(q, Order::Gradient) else {
            return;
        };
        let f = self.law.force(&self.law_state, p.delta, self.rate(&p, v)).force;
        for (d, g) in self.local_dofs[p.element].iter().zip(p.gradient.iter()) {
            if let Some(i) = d {
                out[*i] += f * g;
            }
        }
    }

    fn tangent(
        &self,
        t: f64,
        q: &Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let nb = self.nb;
        self.beam.tangent(t, &q.beam, v.subrows(0, nb), a.subrows(0, nb), w, out);
        for k in 0..3 {
            out.push(nb + k, nb + k, w.inertia * w.da * self.mass);
        }
        // The contact block is pushed for the element nearest to the ball, in or out of
        // contact (zeros), so the sparsity changes only when the ball moves to another element
        // (one symbolic LU analysis then), and the ball is coupled to one element, not to the
        // whole beam.
        let (element, _) = self.nearest_element(q);
        let mut block = SMatrix::<f64, LOCAL, LOCAL>::zeros();
        if let Some(p) = self.touching(q, Order::Hessian) {
            let rate = self.rate(&p, v);
            let cf = self.law.force(&self.law_state, p.delta, rate);
            let gg = p.gradient * p.gradient.transpose();
            block = (gg * cf.stiffness + p.hessian * cf.force) * (w.force * w.dq)
                + gg * (cf.damping * w.force * w.dv);
        }
        let dofs = &self.local_dofs[element];
        for (r, dr) in dofs.iter().enumerate() {
            let Some(i) = dr else { continue };
            for (c, dc) in dofs.iter().enumerate() {
                if let Some(j) = dc {
                    out.push(*i, *j, block[(r, c)]);
                }
            }
        }
    }

    fn force_scale(&self, q: &Config) -> f64 {
        self.beam.force_scale(&q.beam)
    }

    fn configuration_scale(&self, q: &Config) -> f64 {
        self.beam.configuration_scale(&q.beam).max(q.ball.amax())
    }
}

/// Builds the beam of an FE plan: a straight mesh along x, thickness along z.
///
/// # Errors
/// From the beam crate.
pub fn build_beam(target: &FeTarget) -> Result<BeamModel, ImpactError> {
    let section = Section::rectangle(&target.material, target.width, target.thickness)?;
    let mesh = Mesh::from_nodes(
        target.nodes.iter().map(|x| Vector3::new(*x, 0.0, 0.0)).collect(),
        vec![UnitQuaternion::identity(); target.nodes.len()],
        section,
    );
    let last = target.nodes.len() - 1;
    let model = BeamModel::new(mesh)?;
    let (first, end) = match target.support {
        SupportName::ClampedFree => (Support::Clamped, Support::Free),
        SupportName::PinnedPinned => (Support::Pinned, Support::Pinned),
        SupportName::ClampedClamped => (Support::Clamped, Support::Clamped),
        SupportName::ClampedPinned => (Support::Clamped, Support::Pinned),
        SupportName::FreeFree => (Support::Free, Support::Free),
    };
    Ok(model.support(0, first)?.support(last, end)?)
}

/// Runs an FE plan to its end time.
///
/// # Errors
/// `SolverFailed` when Newton fails even after step halving, with the time reached.
pub fn run(plan: &Plan, target: &FeTarget) -> Result<Outcome, ImpactError> {
    match &plan.law {
        Law::Hertz(l) => Run::new(plan, target, l)?.run(),
        Law::HuntCrossley(l) => Run::new(plan, target, l)?.run(),
        Law::Thornton(l) => Run::new(plan, target, l)?.run(),
    }
}

struct Run<'a, L: ContactLaw> {
    plan: &'a Plan,
    target: &'a FeTarget,
    model: BallOnBeam<'a, L>,
    integrator: Integrator,
    state: State<Config>,
    /// Ball centre at first touch (m).
    ball_start: Vector3<f64>,
    /// The impact point's element and local coordinate (material point, fixed).
    impact_element: (usize, f64),
    history: History,
    contacts: Vec<Contact>,
    max_displacement: (f64, f64),
    force: f64,
    steps: usize,
    located: usize,
    newton_iterations: usize,
    halvings: usize,
    /// Contact steps rejected by the error control.
    rejected: usize,
}

impl<'a, L: ContactLaw> Run<'a, L> {
    fn new(plan: &'a Plan, target: &'a FeTarget, law: &'a L) -> Result<Self, ImpactError> {
        let beam = build_beam(target)?;
        let model = BallOnBeam::new(
            beam,
            plan.ball_mass,
            plan.gravity,
            plan.ball_radius,
            0.5 * target.thickness,
            law,
        );
        let scheme = Scheme::hht(target.alpha)
            .map_err(|e| ImpactError::SolverFailed { t: 0.0, reason: e.to_string() })?;
        let mut integrator = Integrator::new(scheme, NewtonOptions::default());
        let ball_start =
            Vector3::new(target.position, 0.0, 0.5 * target.thickness + plan.ball_radius);
        let q = Config { beam: model.beam().reference_state(), ball: ball_start };
        let n = model.ndof();
        let mut v = Col::<f64>::zeros(n);
        v[n - 1] = -plan.speed;
        let state = integrator.initial_state(&model, 0.0, q, v).map_err(|e| fail(0.0, &e))?;
        let i = target.nodes.windows(2).position(|w| target.position <= w[1]).unwrap_or(0);
        let xi = (target.position - target.nodes[i]) / (target.nodes[i + 1] - target.nodes[i]);
        Ok(Self {
            plan,
            target,
            model,
            integrator,
            state,
            ball_start,
            impact_element: (i, xi),
            history: History::default(),
            contacts: Vec::new(),
            max_displacement: (0.0, 0.0),
            force: 0.0,
            steps: 0,
            located: 0,
            newton_iterations: 0,
            halvings: 0,
            rejected: 0,
        })
    }

    /// Beam displacement at the impact point (material point), along the impact direction -z.
    fn beam_displacement(&self) -> f64 {
        let (i, xi) = self.impact_element;
        let e = &self.model.beam().mesh().elements[i];
        let (a, b) = (e.nodes[0], e.nodes[1]);
        let p = &self.state.q.beam.positions;
        -((1.0 - xi) * p[a].z + xi * p[b].z)
    }

    fn ball_position(&self) -> f64 {
        self.ball_start.z - self.state.q.ball.z
    }

    fn ball_velocity(&self) -> f64 {
        -self.state.v[self.state.v.nrows() - 1]
    }

    fn record(&mut self) {
        let p = self.model.contact_point(&self.state.q, Order::Value);
        let e = &self.model.beam().mesh().elements[p.element];
        let nodes = &self.target.nodes;
        let contact_point = nodes[e.nodes[0]] + p.xi * (nodes[e.nodes[1]] - nodes[e.nodes[0]]);
        let energy = self.energy();
        self.history.push(Sample {
            ball_energy: energy.ball_kinetic + energy.ball_potential,
            beam_energy: energy.beam,
            contact_energy: energy.contact_stored,
            dissipated_energy: energy.dissipated,
            time: self.state.t,
            force: self.force,
            approach: p.delta,
            ball_position: self.ball_position(),
            ball_velocity: self.ball_velocity(),
            beam_displacement: self.beam_displacement(),
            contact_point,
        });
    }

    /// One integrator step of `h` from the current state, committing nothing.
    fn trial(&mut self, from: &State<Config>, h: f64) -> Result<State<Config>, ImpactError> {
        let mut s = from.clone();
        let report = self.integrator.step(&self.model, &mut s, h).map_err(|e| fail(from.t, &e))?;
        self.newton_iterations += report.iterations;
        self.halvings += report.substeps.saturating_sub(1);
        Ok(s)
    }

    /// Accepts a state reached by one step: commits the law, updates the force, counters.
    fn accept(&mut self, s: State<Config>) -> Result<(), ImpactError> {
        let (delta, rate, cf) = self.model.contact(&s.q, s.v.as_ref());
        if !(delta.is_finite() && cf.force.is_finite()) {
            return Err(ImpactError::SolverFailed {
                t: s.t,
                reason: "the contact approach or force is not finite".into(),
            });
        }
        self.model.law.commit(&mut self.model.law_state, delta, rate);
        self.model.commit_contact_element(&s.q);
        self.force = if delta > self.model.law.release_approach(&self.model.law_state) {
            cf.force
        } else {
            0.0
        };
        self.state = s;
        self.steps += 1;
        let w = self.beam_displacement();
        if w > self.max_displacement.0 {
            self.max_displacement = (w, self.state.t);
        }
        Ok(())
    }

    /// Step length in (0, h) at which the approach crosses `release`, by the Illinois method on
    /// re-stepped trials from `from` (approach(0) and approach(h) on opposite sides).
    fn locate(
        &mut self,
        from: &State<Config>,
        h: f64,
        release: f64,
        end: &State<Config>,
    ) -> Result<State<Config>, ImpactError> {
        self.located += 1;
        let mut bracket = Illinois::new(
            0.0,
            self.model.approach(&from.q) - release,
            h,
            self.model.approach(&end.q) - release,
        );
        let mut best = end.clone();
        // The approach is located to 1e-4 of the estimated largest approach (or 1e-6 of the
        // step): its error then shifts onset and separation by ~1e-4 of a contact step.
        let tol = 1e-4 * self.target.approach_scale;
        for _ in 0..40 {
            let Some(c) = bracket.trial() else { break };
            let s = self.trial(from, c)?;
            let fc = self.model.approach(&s.q) - release;
            best = s;
            if fc.abs() <= tol || bracket.b - bracket.a <= 1e-6 * h {
                break;
            }
            bracket.narrow(c, fc);
        }
        Ok(best)
    }

    fn run(mut self) -> Result<Outcome, ImpactError> {
        let clock = std::time::Instant::now();
        self.record();
        let end = self.plan.end_time;
        while self.state.t < end * (1.0 - 1e-12) {
            self.contact_phase()?;
            if self.state.t < end * (1.0 - 1e-12) {
                self.free_flight()?;
            }
        }
        Ok(self.finish(clock.elapsed().as_secs_f64()))
    }

    /// Local error of the ball's position over a step from `from` to `to` (m): the
    /// Zienkiewicz-Xie estimate `h^2 |beta - 1/6| |a_1 - a_0|` on the ball's three unknowns.
    fn ball_step_error(&self, from: &State<Config>, to: &State<Config>) -> f64 {
        let n = from.a.nrows();
        let h = to.t - from.t;
        let beta = self.integrator.scheme().beta;
        let jump = (0..3).map(|k| (to.a[n - 3 + k] - from.a[n - 3 + k]).powi(2)).sum::<f64>();
        h * h * (beta - 1.0 / 6.0).abs() * jump.sqrt()
    }

    /// From onset (approach at the release level) to separation or the end time.
    ///
    /// The step starts at the plan's contact step (its smallest) and is adapted to keep the
    /// ball's local position error near `CONTACT_ERROR` x the largest rigid-support approach:
    /// it stays small through a Hertzian pulse (the force changes on the pulse's time scale)
    /// and grows to the free-flight step when a heavy ball rides the beam quasi-statically
    /// (a 1 kg ball stays on the paper's cantilever for ~0.2 s: ~2e5 contact steps otherwise).
    fn contact_phase(&mut self) -> Result<(), ImpactError> {
        let end = self.plan.end_time;
        let (h_min, h_max) = (self.plan.time_step, self.target.free_time_step);
        let tolerance = CONTACT_ERROR * self.target.approach_scale;
        let mut h = h_min;
        let start = self.state.t;
        let velocity_before = self.ball_velocity();
        let mut times = vec![self.state.t];
        let mut forces = vec![self.force];
        let mut approaches = vec![self.model.approach(&self.state.q)];
        let mut impulse = 0.0;
        let mut complete = false;
        let mut steps = 0;
        let stride = (self.target.samples_per_pulse / 100).max(1);
        while self.state.t < end * (1.0 - 1e-12) {
            let tau = h.min(end - self.state.t);
            let from = self.state.clone();
            let f0 = self.force;
            let trial = self.trial(&from, tau)?;
            let release = self.model.law.release_approach(&self.model.law_state);
            let separated = self.model.approach(&trial.q) <= release && steps > 0;
            // Third-order local error: the step that meets the tolerance, with a safety
            // factor, at most doubling and at least a fifth of the last.
            let error = self.ball_step_error(&from, &trial);
            let factor = (0.9 * (tolerance / error.max(f64::MIN_POSITIVE)).cbrt()).clamp(0.2, 2.0);
            if error > tolerance && tau > h_min * (1.0 + 1e-9) {
                self.rejected += 1;
                h = (tau * factor).max(h_min);
                continue;
            }
            let next = if separated { self.locate(&from, tau, release, &trial)? } else { trial };
            let dt = next.t - from.t;
            self.accept(next)?;
            let f1 = if separated { 0.0 } else { self.force };
            self.force = f1;
            impulse += 0.5 * dt * (f0 + f1);
            times.push(self.state.t);
            forces.push(f1);
            approaches.push(self.model.approach(&self.state.q));
            steps += 1;
            if separated {
                complete = true;
                break;
            }
            if steps % stride == 0 {
                self.record();
            }
            h = (tau * factor).clamp(h_min, h_max);
        }
        self.record();
        if forces.iter().all(|f| *f == 0.0) {
            return Ok(());
        }
        self.contacts.push(Contact {
            start,
            duration: self.state.t - start,
            complete,
            peak_force: refined_max(&times, &forces),
            max_approach: refined_max(&times, &approaches),
            impulse,
            ball_velocity_before: velocity_before,
            ball_velocity_after: self.ball_velocity(),
            print_radius: self.model.law.print_radius(&self.model.law_state),
            steps,
        });
        Ok(())
    }

    /// Free flight until the next onset (located) or the end time.
    fn free_flight(&mut self) -> Result<(), ImpactError> {
        let end = self.plan.end_time;
        let (h_contact, h_free) = (self.plan.time_step, self.target.free_time_step);
        let mut next_output = self.state.t + self.plan.output_interval;
        while self.state.t < end * (1.0 - 1e-12) {
            let release = self.model.law.release_approach(&self.model.law_state);
            let (delta, rate, _) = self.model.contact(&self.state.q, self.state.v.as_ref());
            // Do not step past a touch predicted from the gap and the closing speed (plus the
            // ball's gravity); at least one contact step.
            let gap = release - delta;
            let closing = rate.max(0.0) + self.plan.gravity * h_free;
            let mut tau = h_free;
            if closing > 0.0 {
                tau = tau.min((0.5 * gap / closing).max(h_contact));
            }
            let tau = tau.min(end - self.state.t);
            let from = self.state.clone();
            let trial = self.trial(&from, tau)?;
            if self.model.approach(&trial.q) > release {
                let onset =
                    if delta < release { self.locate(&from, tau, release, &trial)? } else { trial };
                self.accept(onset)?;
                self.force = 0.0;
                return Ok(());
            }
            self.accept(trial)?;
            if self.state.t >= next_output || self.state.t >= end * (1.0 - 1e-12) {
                self.record();
                next_output = self.state.t + self.plan.output_interval;
            }
        }
        Ok(())
    }

    /// The energy ledger at the current state.
    fn energy(&self) -> Energy {
        let m = self.plan.ball_mass;
        let law = self.model.law;
        let q = &self.state.q;
        let delta = self.model.approach(q);
        let initial = 0.5 * m * self.plan.speed * self.plan.speed;
        let v = self.state.v.as_ref();
        let n = v.nrows();
        let ball_speed2 = (0..3).map(|k| v[n - 3 + k] * v[n - 3 + k]).sum::<f64>();
        let ball_kinetic = 0.5 * m * ball_speed2;
        let ball_potential = -m * self.plan.gravity * self.ball_position();
        let beam_model = self.model.beam();
        let beam =
            beam_model.strain_energy(&q.beam) + beam_model.kinetic_energy(v.subrows(0, n - 3));
        let contact_stored = law.stored_energy(&self.model.law_state, delta);
        let dissipated = law.dissipated_energy(&self.model.law_state);
        Energy::new(initial, ball_kinetic, ball_potential, beam, contact_stored, dissipated)
    }

    fn finish(self, wall_time: f64) -> Outcome {
        let plan = self.plan;
        let energy = self.energy();
        let mut warnings = plan.warnings.clone();
        let static_stiffness =
            static_stiffness(&self.target.analytic, self.target.position, &mut warnings);
        let mut summary = plan.summary.clone();
        summary.reasons.push(format!(
            "{} HHT steps ({} Newton iterations, {} step halvings, {} contact steps rejected by the error control), {} events located by re-stepping",
            self.steps, self.newton_iterations, self.halvings, self.rejected, self.located
        ));
        let report = Report::assemble(
            plan,
            Ending {
                plan: summary,
                warnings,
                contacts: self.contacts,
                max_displacement: self.max_displacement,
                static_stiffness,
                energy,
                wall_time,
            },
        );
        Outcome { report, history: self.history }
    }
}

fn fail(t: f64, e: &hht::HhtError) -> ImpactError {
    ImpactError::SolverFailed { t, reason: e.to_string() }
}
