//! The ball on the Simo beam as one [`hht::Model`]: the beam's unknowns, the ball centre's
//! three, and the contact force between them.
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
//! **Contact element.** The element found at the last accepted step is kept while the ball
//! projects on it (within [`STICKY_REACH`] past its ends), so a ball over a node does not switch
//! elements between Newton iterations.

use faer::{ColMut, ColRef};
use hertz::ContactLaw;
use hht::{Model, NewtonWeights, Triplets};
use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};
use simo_beam::{BeamModel, BeamState};

/// BallOnBeamConfiguration of the coupled model: the beam's and the ball centre's (m).
#[derive(Debug, Clone)]
pub struct BallOnBeamConfig {
    /// The beam.
    pub beam: BeamState,
    /// Ball centre (m).
    pub ball: Vector3<f64>,
}

/// How many derivatives of the approach to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    Value,
    Gradient,
    Hessian,
}

/// Unknowns of one contact element: ball (3), node a (6), node b (6).
const LOCAL: usize = 15;

/// The contact kinematics at a configuration: which element, where, and delta with its
/// gradient and Hessian over the element's 15 local unknowns.
#[derive(Debug, Clone)]
pub(crate) struct ContactPoint {
    pub(crate) element: usize,
    pub(crate) xi: f64,
    pub(crate) delta: f64,
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
    pub(crate) law: &'a L,
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
pub(crate) const STICKY_REACH: f64 = 0.05;

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
    pub fn commit_contact_element(&mut self, q: &BallOnBeamConfig) {
        self.sticky_element = Some(self.nearest_element(q).0);
    }

    /// The contact element and the clamped projection on it: the sticky element while the
    /// ball centre projects within [`STICKY_REACH`] of it, otherwise the element whose chord
    /// passes nearest to the ball centre.
    fn nearest_element(&self, q: &BallOnBeamConfig) -> (usize, f64) {
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
    pub(crate) fn approach(&self, q: &BallOnBeamConfig) -> f64 {
        self.contact_point(q, Order::Value).delta
    }

    /// The contact point with derivatives up to `order` (the others left zero): the residual
    /// needs the gradient, only the Newton matrix in contact needs the Hessian.
    pub(crate) fn contact_point(&self, q: &BallOnBeamConfig, order: Order) -> ContactPoint {
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
    fn touching(&self, q: &BallOnBeamConfig, order: Order) -> Option<ContactPoint> {
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
    pub(crate) fn contact(
        &self,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
    ) -> (f64, f64, hertz::ContactForce) {
        let p = self.contact_point(q, Order::Gradient);
        let rate = self.rate(&p, v);
        (p.delta, rate, self.law.force(&self.law_state, p.delta, rate))
    }

    fn ball(&self, x: ColRef<'_, f64>) -> Vector3<f64> {
        Vector3::new(x[self.nb], x[self.nb + 1], x[self.nb + 2])
    }
}

impl<L: ContactLaw> Model for BallOnBeam<'_, L> {
    type Config = BallOnBeamConfig;

    fn ndof(&self) -> usize {
        self.nb + 3
    }

    fn update(&self, q: &mut BallOnBeamConfig, dq: ColRef<'_, f64>) {
        self.beam.update(&mut q.beam, dq.subrows(0, self.nb));
        q.ball += self.ball(dq);
    }

    fn inertial_force(
        &self,
        q: &BallOnBeamConfig,
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

    fn net_force(
        &self,
        t: f64,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
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
        q: &BallOnBeamConfig,
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

    fn force_scale(&self, q: &BallOnBeamConfig) -> f64 {
        self.beam.force_scale(&q.beam)
    }

    fn configuration_scale(&self, q: &BallOnBeamConfig) -> f64 {
        self.beam.configuration_scale(&q.beam).max(q.ball.amax())
    }
}
