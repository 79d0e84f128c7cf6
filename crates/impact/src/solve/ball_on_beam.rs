//! The ball on the geometrically exact beam as one [`hht::Model`]: the planar beam's unknowns
//! (x, z, theta a node), the ball centre's two (x, z), and the contact force between them.
//!
//! **Why planar.** The ball strikes the beam's face along its thickness (z) and nothing pushes
//! either out of the x-z plane, so the motion stays in it: [`simo_beam::PlanarBeam`] carries it
//! with three unknowns a node instead of the 3D beam's six, with the same discrete equations
//! (the simo-beam tests compare the two), an analytic tangent and a banded Newton matrix.
//!
//! **Model.** The beam lies along x from the first support, its thickness along z; the ball is
//! a rigid sphere of mass m, starting at first touch above the top face at the impact point
//! and moving along -z. Gravity acts on the ball only (the beam's own sag is the reference
//! state, as in the modal method).
//!
//! **Contact.** Frictionless, node-to-segment style: for the ball centre c the contact element
//! is the element whose chord (x_a, x_b) passes nearest to c; on it the contact point is the
//! projection `xi = (c - x_a).t / t.t`, `x = x_a + xi t`, the face normal is the interpolated
//! section normal `n = normalise((1 - xi) n_a + xi n_b)` (`n_i = (-sin theta_i, cos theta_i)`,
//! so it turns with the sections) and the approach is
//!
//! `delta = R + h/2 - (c - x).n`
//!
//! (positive in compression; the struck face is half the thickness h from the centre line).
//! The contact force F = law(delta, delta-dot) does the virtual work `-F d(delta)`: its
//! generalised force is `F grad(delta)` over the 8 unknowns it touches (ball, and x, z, theta
//! of both nodes), and its Newton matrix is `k grad grad^T + F Hess(delta)` (+ the damping
//! term `c grad grad^T` times dv/dq), where gradient and Hessian come from second-order
//! forward differentiation (num-dual) of the formula above, so the geometric terms of the
//! sliding contact point and turning normal are all in it. The rotations are additive in the
//! plane, so the Hessian is exact.
//!
//! **Contact element.** The element found at the last accepted step is kept while the ball
//! projects on it (within [`STICKY_REACH`] past its ends), so a ball over a node does not switch
//! elements between Newton iterations.

use faer::{ColMut, ColRef};
use hertz::ContactLaw;
use hht::{Band, Model, NewtonWeights, Triplets};
use nalgebra::{SMatrix, SVector, Vector2};
use num_dual::Dual2SVec64;
use simo_beam::{PlanarBeam, PlanarState};
use std::cell::{Cell, RefCell};

/// Configuration of the coupled model: the beam's and the ball centre's (x, z) (m).
#[derive(Debug)]
pub struct BallOnBeamConfig {
    /// The beam.
    pub beam: PlanarState,
    /// Ball centre (x, z) (m).
    pub ball: Vector2<f64>,
}

impl Clone for BallOnBeamConfig {
    fn clone(&self) -> Self {
        Self { beam: self.beam.clone(), ball: self.ball }
    }

    /// Reuses the beam's allocations (see [`PlanarState`]'s `clone_from`).
    fn clone_from(&mut self, source: &Self) {
        self.beam.clone_from(&source.beam);
        self.ball = source.ball;
    }
}

/// How many derivatives of the approach to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Order {
    Value,
    Gradient,
    Hessian,
}

/// Unknowns of one contact element: ball (2), node a (3), node b (3).
const LOCAL: usize = 8;

/// The contact kinematics at a configuration: which element, where, and delta with its
/// gradient and Hessian over the contact's `N` local unknowns (the ball's and the element's
/// nodes': 8 in the plane, 15 in 3D).
#[derive(Debug, Clone)]
pub(crate) struct ContactPoint<const N: usize = LOCAL> {
    pub(crate) element: usize,
    pub(crate) xi: f64,
    pub(crate) delta: f64,
    pub(crate) gradient: SVector<f64, N>,
    /// Asked for ([`Order::Hessian`]) only in the Newton matrix; boxed, so that the point a
    /// residual asks for twice a step (and the copy kept of it) is a few numbers, not an
    /// N x N matrix of zeros (15 x 15 in 3D).
    pub(crate) hessian: Option<Box<SMatrix<f64, N, N>>>,
}

impl<const N: usize> ContactPoint<N> {
    /// delta-dot = grad(delta) . the local unknowns' velocities (`dofs` their equation
    /// numbers, `None` where held).
    pub(crate) fn rate(&self, dofs: &[Option<usize>; N], v: ColRef<'_, f64>) -> f64 {
        dofs.iter().zip(self.gradient.iter()).map(|(d, g)| d.map_or(0.0, |i| g * v[i])).sum()
    }

    /// Adds the contact force's generalised force `F grad(delta)` to `out`.
    pub(crate) fn add_force(
        &self,
        dofs: &[Option<usize>; N],
        force: f64,
        mut out: ColMut<'_, f64>,
    ) {
        for (d, g) in dofs.iter().zip(self.gradient.iter()) {
            if let Some(i) = d {
                out[*i] += force * g;
            }
        }
    }

    /// Pushes the contact's Newton block, `k grad grad^T + F Hess(delta)` (+ the damping term
    /// `c grad grad^T` times dv/dq), weighted by `w`.
    pub(crate) fn push_block(
        &self,
        dofs: &[Option<usize>; N],
        cf: &hertz::ContactForce,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let gg = self.gradient * self.gradient.transpose();
        let stiffness = match &self.hessian {
            Some(hessian) => gg * cf.stiffness + **hessian * cf.force,
            None => gg * cf.stiffness,
        };
        let block = stiffness * (w.force * w.dq) + gg * (cf.damping * w.force * w.dv);
        for (r, dr) in dofs.iter().enumerate() {
            let Some(i) = dr else { continue };
            for (c, dc) in dofs.iter().enumerate() {
                if let Some(j) = dc {
                    out.push(*i, *j, block[(r, c)]);
                }
            }
        }
    }
}

/// The coupled ball-beam-contact model for [`hht`].
pub struct BallOnBeam<'a, L: ContactLaw> {
    beam: PlanarBeam,
    nb: usize,
    mass: f64,
    gravity: f64,
    radius: f64,
    half_thickness: f64,
    pub(crate) law: &'a L,
    /// The law's history, committed after every accepted step.
    pub law_state: L::State,
    /// Global equation numbers of each element's 8 local unknowns.
    local_dofs: Vec<[Option<usize>; LOCAL]>,
    /// The contact element of the last accepted step, kept while the projection stays on it
    /// (see [`BallOnBeam::nearest_element`]).
    sticky_element: Option<usize>,
    /// The last contact point computed, with its element and the 8 numbers it was computed
    /// from (ball centre, the element's nodes): a step asks for the same one up to five
    /// times (the converged residual, the step's acceptance, the approach's rate, the
    /// separation test, the history), and it is a pure function of those.
    last: RefCell<Option<Memo>>,
    /// Each element's section strains at the last net force (extensions, shears, curvatures,
    /// an array each), from the same pass, and how many net forces have been evaluated (see
    /// [`super::struck::Struck::force_passes`]).
    last_strains: RefCell<[Vec<f64>; 3]>,
    force_passes: Cell<u64>,
}

/// A contact point with what it was computed from: the element, the 8 numbers, the order.
type Memo = (usize, [f64; LOCAL], Order, ContactPoint);

/// How far past its ends (in element lengths) the projection may fall on the sticky element
/// before the nearest element is searched again. Without it a ball over a node flips between
/// the two elements from one Newton iteration to the next (equal approach, different
/// derivatives): Newton then oscillated with the residual's sign and halved the step.
pub(crate) const STICKY_REACH: f64 = 0.05;

/// The surface an element offers the ball: its face, and at an end of the beam also the
/// corner where the face meets the end.
#[derive(Debug, Clone, Copy)]
struct Surface {
    /// Ball radius R (m).
    radius: f64,
    /// Half the thickness h/2 (m): the face's distance from the centre line.
    half_thickness: f64,
    /// Whether the element's first node is the beam's first, and its second the beam's last.
    ends: (bool, bool),
}

/// The approach for local unknowns `u` = (ball x, z; node a x, z, theta; node b likewise) added
/// to the configuration given (`c0` the ball, `a0` and `b0` the nodes). On a face it is
/// `delta = R + h/2 - |(c - x).n|`: the struck face (+n) at first, the other (-n) where the
/// ball has got below the beam, as a heavy ball does once it has slid off the end and the
/// beam swings back onto it (a one-sided face would read that ball as pressed metres deep).
/// Past an end of the beam (the projection beyond a first or last node) the ball can only
/// touch a corner, `p = x_end +- (h/2) n_end` on its side, and `delta = R - |c - p|`: the two
/// agree where the ball is right above the corner, so the approach is continuous as the ball
/// slides off the end, where extrapolating the face would meet a beam that is not there.
fn approach_of<T: nalgebra::RealField + Copy>(
    u: &SVector<T, LOCAL>,
    c0: &Vector2<f64>,
    a0: [f64; 3],
    b0: [f64; 3],
    surface: Surface,
) -> T {
    let lift = nalgebra::convert::<f64, T>;
    let c = Vector2::new(lift(c0.x) + u[0], lift(c0.y) + u[1]);
    let xa = Vector2::new(lift(a0[0]) + u[2], lift(a0[1]) + u[3]);
    let xb = Vector2::new(lift(b0[0]) + u[5], lift(b0[1]) + u[6]);
    let normal = |theta: T| Vector2::new(-theta.sin(), theta.cos());
    let (na, nb) = (normal(lift(a0[2]) + u[4]), normal(lift(b0[2]) + u[7]));
    let t = xb - xa;
    let xi = (c - xa).dot(&t) / t.dot(&t);
    let half = lift(surface.half_thickness);
    let corner = |x: Vector2<T>, n: Vector2<T>| {
        let side = if (c - x).dot(&n) < T::zero() { -half } else { half };
        lift(surface.radius) - (c - (x + n * side)).norm()
    };
    if surface.ends.0 && xi < T::zero() {
        return corner(xa, na);
    }
    if surface.ends.1 && xi > T::one() {
        return corner(xb, nb);
    }
    let x = xa + t * xi;
    let d = na * (T::one() - xi) + nb * xi;
    let n = d / d.norm();
    lift(surface.radius) + half - (c - x).dot(&n).abs()
}

/// The terms of the approach on a face and of its derivatives, in the plane or in space (`D`
/// = 2, 3), from the ball centre `c`, the element's ends `x_a`, `x_b` and the face normals
/// there `n_a`, `n_b`: `t = x_b - x_a`, `ca = c - x_a`, `xi = ca.t / t.t`, `x = x_a + xi t`,
/// `d = (1 - xi) n_a + xi n_b`, `n = d / |d|`, `g = (c - x).n`, and for `dg = n.(dc - dx) +
/// p.dd`: `p = (I - n n^T)(c - x) / |d|`; `dxi = (dca.t + ca.dt - 2 xi t.dt) / t.t` enters
/// `dg` times `K = -n.t + p.(n_b - n_a)`. Each model's `approach_gradient` turns `dd` into
/// its rotation unknowns.
pub(crate) struct FaceTerms<const D: usize> {
    /// Where along the element the ball is over, `xi`.
    pub(crate) xi: f64,
    /// The ball centre's height over the centre line along the normal, `g` (m).
    pub(crate) g: f64,
    /// `p`, whose product with the normal's turn `dd` is `g`'s change by it.
    pub(crate) p: SVector<f64, D>,
    /// The gradients of g over c, x_a and x_b.
    pub(crate) dc: SVector<f64, D>,
    pub(crate) da: SVector<f64, D>,
    pub(crate) db: SVector<f64, D>,
}

impl<const D: usize> FaceTerms<D> {
    pub(crate) fn new(
        c: &SVector<f64, D>,
        (xa, xb): (&SVector<f64, D>, &SVector<f64, D>),
        (na, nb): (&SVector<f64, D>, &SVector<f64, D>),
    ) -> Self {
        let t = xb - xa;
        let tt = t.dot(&t);
        let ca = c - xa;
        let xi = ca.dot(&t) / tt;
        let x = xa + t * xi;
        let d = na * (1.0 - xi) + nb * xi;
        let size = d.norm();
        let n = d / size;
        let cx = c - x;
        let g = cx.dot(&n);
        let p = (cx - n * g) / size;
        let k = (p.dot(&(nb - na)) - n.dot(&t)) / tt;
        Self {
            xi,
            g,
            p,
            dc: n + t * k,
            da: -n * (1.0 - xi) + (t * (2.0 * xi) - t - ca) * k,
            db: -n * xi + (ca - t * (2.0 * xi)) * k,
        }
    }
}

/// The approach at zero increments and its gradient over the local unknowns, by the
/// derivatives of [`approach_of`]'s formulas written out (one pass of plain arithmetic; the
/// 3D model's `approach_gradient` has the same derivation). The normal `n(theta) =
/// (-sin theta, cos theta)` turns at `m = dn/dtheta = (-cos theta, -sin theta)`.
///
/// On the face, `delta = R + h/2 - |g|` by [`FaceTerms`], the normals' turns
/// `dd = (1 - xi) m_a dtheta_a + xi m_b dtheta_b`. Past an end, the corner `x_e + s n_e`
/// (s = +-h/2, the side), `w = c - x_e - s n_e` and `delta = R - |w|`:
/// `d|w| = w^.(dc - dx_e - s m_e dtheta_e)`.
fn approach_gradient(
    c: &Vector2<f64>,
    a0: [f64; 3],
    b0: [f64; 3],
    surface: Surface,
) -> (f64, SVector<f64, LOCAL>) {
    let mut gradient = SVector::<f64, LOCAL>::zeros();
    let (xa, xb) = (Vector2::new(a0[0], a0[1]), Vector2::new(b0[0], b0[1]));
    let normal = |theta: f64| Vector2::new(-theta.sin(), theta.cos());
    // m = dn/dtheta is n turned a right angle back: (-cos, -sin) from n = (-sin, cos).
    let turning = |n: Vector2<f64>| Vector2::new(-n.y, n.x);
    let (na, nb) = (normal(a0[2]), normal(b0[2]));
    let t = xb - xa;
    let xi = (c - xa).dot(&t) / t.dot(&t);
    let half = surface.half_thickness;
    // Past an end: the corner of the end node `(x, n)`, its unknowns from `at`.
    let past = match surface.ends {
        (true, _) if xi < 0.0 => Some((xa, na, 2)),
        (_, true) if xi > 1.0 => Some((xb, nb, 5)),
        _ => None,
    };
    if let Some((x, n, at)) = past {
        let side = if (c - x).dot(&n) < 0.0 { -half } else { half };
        let w = c - (x + n * side);
        let size = w.norm();
        let unit = w / size;
        gradient.fixed_rows_mut::<2>(0).copy_from(&-unit);
        gradient.fixed_rows_mut::<2>(at).copy_from(&unit);
        gradient[at + 2] = side * unit.dot(&turning(n));
        return (surface.radius - size, gradient);
    }
    let f = FaceTerms::new(c, (&xa, &xb), (&na, &nb));
    // The gradient of g, then of delta = R + h/2 - |g|; n_a turns by m_a d theta_a.
    let sign = if f.g < 0.0 { 1.0 } else { -1.0 };
    gradient.fixed_rows_mut::<2>(0).copy_from(&(f.dc * sign));
    gradient.fixed_rows_mut::<2>(2).copy_from(&(f.da * sign));
    gradient[4] = (1.0 - f.xi) * f.p.dot(&turning(na)) * sign;
    gradient.fixed_rows_mut::<2>(5).copy_from(&(f.db * sign));
    gradient[7] = f.xi * f.p.dot(&turning(nb)) * sign;
    (surface.radius + half - f.g.abs(), gradient)
}

impl<'a, L: ContactLaw> BallOnBeam<'a, L> {
    /// The coupled model: `beam`, a ball of `mass` (kg) and `radius` (m) under `gravity`
    /// (m/s^2, along -z), a struck face `half_thickness` (m) above the centre line, and `law`.
    pub fn new(
        beam: PlanarBeam,
        mass: f64,
        gravity: f64,
        radius: f64,
        half_thickness: f64,
        law: &'a L,
    ) -> Self {
        let nb = beam.ndof();
        let local_dofs = (0..beam.elements())
            .map(|e| {
                let mut d = [None; LOCAL];
                d[0] = Some(nb);
                d[1] = Some(nb + 1);
                for (end, node) in [e, e + 1].into_iter().enumerate() {
                    for k in 0..3 {
                        d[2 + 3 * end + k] = beam.dof(node, k);
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
            last: RefCell::new(None),
            last_strains: RefCell::default(),
            force_passes: Cell::new(0),
        }
    }

    /// The beam model.
    pub fn beam(&self) -> &PlanarBeam {
        &self.beam
    }

    /// How many net forces have been evaluated (see
    /// [`super::struck::Struck::force_passes`]).
    pub(crate) fn force_passes(&self) -> u64 {
        self.force_passes.get()
    }

    /// Every element's section strains at the configuration of the last net force, from that
    /// pass, into `out`; `false`, and `out` untouched, before any net force.
    pub(crate) fn last_pass_strains(&self, out: &mut [(f64, f64, f64)]) -> bool {
        let kept = self.last_strains.borrow();
        let [extensions, shears, curvatures] = &*kept;
        if extensions.is_empty() {
            return false;
        }
        let each = extensions.iter().zip(shears).zip(curvatures);
        for (o, ((e, s), c)) in out.iter_mut().zip(each) {
            *o = (*e, *s, *c);
        }
        true
    }

    /// Keeps the contact element of configuration `q` (an accepted step) for the next steps.
    pub fn commit_contact_element(&mut self, q: &BallOnBeamConfig) {
        self.sticky_element = Some(self.nearest_element(q).0);
    }

    /// Chord of element `e`: its first node and the vector to its second (m).
    fn chord(q: &PlanarState, e: usize) -> (Vector2<f64>, Vector2<f64>) {
        let xa = Vector2::new(q.x[e], q.z[e]);
        (xa, Vector2::new(q.x[e + 1], q.z[e + 1]) - xa)
    }

    /// The contact element and the clamped projection on it: the sticky element while the
    /// ball centre projects within [`STICKY_REACH`] of it, otherwise the element whose chord
    /// passes nearest to the ball centre.
    fn nearest_element(&self, q: &BallOnBeamConfig) -> (usize, f64) {
        if let Some(i) = self.sticky_element {
            let (xa, t) = Self::chord(&q.beam, i);
            let xi = (q.ball - xa).dot(&t) / t.dot(&t);
            if (-STICKY_REACH..=1.0 + STICKY_REACH).contains(&xi) {
                return (i, xi.clamp(0.0, 1.0));
            }
        }
        let mut best = (0, 0.0, f64::INFINITY);
        for i in 0..self.beam.elements() {
            let (xa, t) = Self::chord(&q.beam, i);
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
        let node = |i: usize| [q.beam.x[i], q.beam.z[i], q.beam.theta[i]];
        let (a0, b0) = (node(element), node(element + 1));
        let key = [q.ball.x, q.ball.y, a0[0], a0[1], a0[2], b0[0], b0[1], b0[2]];
        if let Some((e, k, o, p)) = &*self.last.borrow() {
            let same = *e == element && k.iter().zip(&key).all(|(a, b)| a.to_bits() == b.to_bits());
            if same && *o >= order {
                return p.clone();
            }
        }
        let p = self.compute_contact_point(q, order, element, xi, (a0, b0));
        *self.last.borrow_mut() = Some((element, key, order, p.clone()));
        p
    }

    /// [`BallOnBeam::contact_point`] on `element` at `xi`, its nodes being `a0` and `b0`.
    fn compute_contact_point(
        &self,
        q: &BallOnBeamConfig,
        order: Order,
        element: usize,
        xi: f64,
        (a0, b0): ([f64; 3], [f64; 3]),
    ) -> ContactPoint {
        let surface = Surface {
            radius: self.radius,
            half_thickness: self.half_thickness,
            ends: (element == 0, element + 1 == self.beam.elements()),
        };
        let c = &q.ball;
        let zero = SVector::<f64, LOCAL>::zeros();
        let (delta, gradient, hessian) = match order {
            Order::Value => (approach_of(&zero, c, a0, b0, surface), SVector::zeros(), None),
            Order::Gradient => {
                let (d, g) = approach_gradient(c, a0, b0, surface);
                (d, g, None)
            }
            Order::Hessian => {
                let (d, g, h) = num_dual::hessian(
                    |u: SVector<Dual2SVec64<LOCAL>, LOCAL>| approach_of(&u, c, a0, b0, surface),
                    &zero,
                );
                (d, g, Some(Box::new(h)))
            }
        };
        ContactPoint { element, xi, delta, gradient, hessian }
    }

    /// The contact point with the gradient if the ball touches (`None` otherwise).
    fn touching(&self, q: &BallOnBeamConfig, order: Order) -> Option<ContactPoint> {
        let release = self.law.release_approach(&self.law_state);
        // In contact (the last point computed touched), the derivatives at once: the value
        // first and then the point again with them cost two evaluations a pass in contact.
        let was = self.last.borrow().as_ref().is_some_and(|(.., p)| p.delta > release);
        let p = self.contact_point(q, if was { order } else { Order::Value });
        (p.delta > release).then(|| if was { p } else { self.contact_point(q, order) })
    }

    /// delta-dot = grad(delta) . local velocities.
    fn rate(&self, p: &ContactPoint, v: ColRef<'_, f64>) -> f64 {
        p.rate(&self.local_dofs[p.element], v)
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

    fn ball(&self, x: ColRef<'_, f64>) -> Vector2<f64> {
        Vector2::new(x[self.nb], x[self.nb + 1])
    }

    /// The Newton matrix's terms of the ball: its mass and, in contact, the contact's block.
    fn ball_tangent(
        &self,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let nb = self.nb;
        for k in 0..2 {
            out.push(nb + k, nb + k, w.inertia * w.da * self.mass);
        }
        // The contact block couples the ball to the element nearest to it, the border of the
        // banded Newton matrix; it is pushed only in contact.
        let Some(p) = self.touching(q, Order::Hessian) else {
            return;
        };
        let cf = self.law.force(&self.law_state, p.delta, self.rate(&p, v));
        p.push_block(&self.local_dofs[p.element], &cf, w, out);
    }
}

impl<L: ContactLaw> Model for BallOnBeam<'_, L> {
    type Config = BallOnBeamConfig;

    fn ndof(&self) -> usize {
        self.nb + 2
    }

    fn update(&self, q: &mut BallOnBeamConfig, dq: ColRef<'_, f64>) {
        self.beam.update(&mut q.beam, dq.subrows(0, self.nb));
        q.ball += self.ball(dq);
    }

    fn displaced(&self, q: &BallOnBeamConfig, dq: ColRef<'_, f64>, out: &mut BallOnBeamConfig) {
        self.beam.displaced(&q.beam, dq.subrows(0, self.nb), &mut out.beam);
        out.ball = q.ball + self.ball(dq);
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
        for k in 0..2 {
            out[nb + k] = self.mass * a[nb + k];
        }
    }

    /// The beam's constant mass matrix and the ball's mass.
    fn constant_mass(&self) -> bool {
        self.beam.constant_mass()
    }

    fn net_force(
        &self,
        _t: f64,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
        let nb = self.nb;
        // The pass's strains kept: an accepted state is its step's last iterate, whose strains
        // then need no pass of their own.
        let mut kept = self.last_strains.borrow_mut();
        for s in kept.iter_mut() {
            s.resize(self.beam.elements(), 0.0);
        }
        let [extensions, shears, curvatures] = &mut *kept;
        let strains = [&mut extensions[..], &mut shears[..], &mut curvatures[..]];
        match out.as_mut().subrows_mut(0, nb).try_as_col_major_mut() {
            Some(beam) => {
                self.beam.internal_force_and_strains(&q.beam, beam.as_slice_mut(), strains)
            }
            None => {
                let mut force = vec![0.0; nb];
                self.beam.internal_force_and_strains(&q.beam, &mut force, strains);
                for (i, f) in force.into_iter().enumerate() {
                    out[i] = f;
                }
            }
        }
        drop(kept);
        self.force_passes.set(self.force_passes.get() + 1);
        // Gravity pulls the ball along -z: net force = -(external) = +m g e_z.
        out[nb] = 0.0;
        out[nb + 1] = self.mass * self.gravity;
        let Some(p) = self.touching(q, Order::Gradient) else {
            return;
        };
        let f = self.law.force(&self.law_state, p.delta, self.rate(&p, v)).force;
        p.add_force(&self.local_dofs[p.element], f, out);
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
        self.ball_tangent(q, v, w, out);
    }

    /// The beam's terms slow (its stiffness changes little from step to step), the ball's and
    /// the contact's fast.
    fn tangent_parts(
        &self,
        t: f64,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        w: NewtonWeights,
        slow: Option<&mut Triplets>,
        fast: &mut Triplets,
    ) {
        let nb = self.nb;
        if let Some(slow) = slow {
            self.beam.tangent(t, &q.beam, v.subrows(0, nb), a.subrows(0, nb), w, slow);
        }
        self.ball_tangent(q, v, w, fast);
    }

    fn force_scale(&self, q: &BallOnBeamConfig) -> f64 {
        self.beam.force_scale(&q.beam)
    }

    fn configuration_scale(&self, q: &BallOnBeamConfig) -> f64 {
        self.beam.configuration_scale(&q.beam).max(q.ball.amax())
    }

    /// The ball's rows: its inertia is a round-off of the beam's forces for a small ball.
    fn own_balance_rows(&self) -> std::ops::Range<usize> {
        let n = self.ndof();
        n - 2..n
    }

    fn band(&self) -> Option<Band> {
        self.beam.band().map(|b| Band { half_bandwidth: b.half_bandwidth, border: 2 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_written_out_gradient_is_the_dual_numbers_one() {
        // On the face and past either end, the ball above and below, at a bent element: the
        // same approach and gradient as dual numbers give, to round-off.
        let (a0, b0) = ([0.0, 1e-4, 3e-3], [1.0, -2e-4, -4e-3]);
        let cases = [
            (Vector2::new(0.6, 0.0074), (false, false)),
            (Vector2::new(0.3, -0.0073), (true, true)),
            (Vector2::new(1.003, 0.0071), (false, true)),
            (Vector2::new(1.002, -0.0072), (true, true)),
            (Vector2::new(-0.002, 0.0073), (true, false)),
        ];
        for (c, ends) in cases {
            let surface = Surface { radius: 0.005, half_thickness: 0.0025, ends };
            let (delta, g) = approach_gradient(&c, a0, b0, surface);
            let (reference, expected) = num_dual::gradient(
                |u: SVector<num_dual::DualSVec64<LOCAL>, LOCAL>| {
                    approach_of(&u, &c, a0, b0, surface)
                },
                &SVector::<f64, LOCAL>::zeros(),
            );
            assert!((delta - reference).abs() < 1e-16, "{c:?}: {delta} vs {reference}");
            for i in 0..LOCAL {
                assert!(
                    (g[i] - expected[i]).abs() < 1e-12 * (1.0 + expected[i].abs()),
                    "{c:?} unknown {i}: {} vs {}",
                    g[i],
                    expected[i]
                );
            }
        }
    }

    /// A flat last element from x = 0 to 1 (m), 5 mm thick, a 5 mm ball.
    fn approach(ball: Vector2<f64>) -> f64 {
        let surface = Surface { radius: 0.005, half_thickness: 0.0025, ends: (false, true) };
        approach_of(
            &SVector::<f64, LOCAL>::zeros(),
            &ball,
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            surface,
        )
    }

    #[test]
    fn a_kept_contact_point_is_the_one_of_the_same_numbers() {
        // The ball pressed 1 um into the last of 4 elements of a 1 m strip: the point kept
        // from a value-only call is not served for a gradient, and a moved ball or beam gets
        // its own point, the same as a model that never computed another.
        #![allow(clippy::unwrap_used)]
        let steel = simo_beam::Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = simo_beam::Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let beam = || PlanarBeam::new(&[0.0, 0.25, 0.5, 0.75, 1.0], &section).unwrap();
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam::new(beam(), 0.01, 0.0, 0.005, 0.0025, &law);
        let mut q = BallOnBeamConfig {
            beam: beam().reference_state(),
            ball: Vector2::new(0.9, 0.0075 - 1e-6),
        };
        let value = model.contact_point(&q, Order::Value);
        let gradient = model.contact_point(&q, Order::Gradient);
        assert!((value.delta - 1e-6).abs() < 1e-15 && (gradient.delta - value.delta).abs() == 0.0);
        // d delta / d (ball z) = -1 on the upper face.
        assert!((gradient.gradient[1] + 1.0).abs() < 1e-12, "{:?}", gradient.gradient);
        for moved in [0, 1] {
            if moved == 0 {
                q.ball.y -= 1e-7;
            } else {
                q.beam.z[4] += 1e-7;
            }
            let fresh = BallOnBeam::new(beam(), 0.01, 0.0, 0.005, 0.0025, &law);
            let (kept, new) = (
                model.contact_point(&q, Order::Gradient),
                fresh.contact_point(&q, Order::Gradient),
            );
            assert!((kept.delta - new.delta).abs() == 0.0 && kept.gradient == new.gradient);
            assert!((kept.delta - value.delta).abs() > 5e-8, "{moved}: {}", kept.delta);
        }
    }

    #[test]
    fn an_accepted_state_s_strains_are_its_last_force_pass_s_or_their_own() {
        // The strains handed on from the last net force's pass are that configuration's;
        // without it they are computed: both the beam's own strains, to the bit. Each net force
        // is counted.
        #![allow(clippy::unwrap_used)]
        use crate::solve::struck::Struck;
        let steel = simo_beam::Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = simo_beam::Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let beam = PlanarBeam::new(&[0.0, 0.25, 0.5, 0.75, 1.0], &section)
            .unwrap()
            .support(0, simo_beam::Support::Clamped)
            .unwrap();
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam::new(beam, 0.01, 0.0, 0.005, 0.0025, &law);
        let state = |k: f64| {
            let mut beam = model.beam().reference_state();
            for i in 0..5 {
                let s = i as f64 / 4.0;
                (beam.z[i], beam.theta[i]) = (1e-3 * k * s * s, 2e-3 * k * s);
            }
            BallOnBeamConfig { beam, ball: Vector2::new(0.9, 0.01) }
        };
        let (a, b) = (state(1.0), state(2.0));
        let n = hht::Model::ndof(&model);
        let mut force = faer::Col::<f64>::zeros(n);
        assert!(!model.last_pass_strains(&mut [(0.0, 0.0, 0.0); 4]));
        hht::Model::net_force(&model, 0.0, &a, faer::Col::zeros(n).as_ref(), force.as_mut());
        assert_eq!(Struck::force_passes(&model), 1);
        let mut kept = vec![(9.0, 9.0, 9.0); 4];
        assert!(model.last_pass_strains(&mut kept) && kept.iter().all(|s| s.2 > 0.0));
        for (q, last_pass) in [(&a, true), (&b, false), (&a, false), (&a, true)] {
            let mut out = vec![(9.0, 9.0, 9.0); 4];
            model.section_strains(q, &mut out, &mut [], last_pass);
            let mut alone = vec![(0.0, 0.0, 0.0); 4];
            model.beam().all_section_strains(&q.beam, &mut alone);
            assert_eq!(out, alone);
        }
    }

    #[test]
    fn the_approach_is_continuous_off_the_end_and_two_sided() {
        // Sliding over the end at 1 um into the face: the face and the corner give the same
        // approach where the ball is right above the corner (to round-off), and it falls
        // smoothly past it (a 0.1 mm slide beyond the end lowers it by ~R (0.1/R)^2/2 = 1 um).
        let z = 0.0025 + 0.005 - 1e-6;
        let on = approach(Vector2::new(1.0 - 1e-12, z));
        let off = approach(Vector2::new(1.0 + 1e-12, z));
        assert!((on - 1e-6).abs() < 1e-15 && (off - 1e-6).abs() < 1e-15, "{on:e} {off:e}");
        let beyond = approach(Vector2::new(1.0 + 1e-4, z));
        assert!((beyond - (1e-6 - 1e-6)).abs() < 2e-7, "{beyond:e}");
        // Far past the end there is no contact, however low the ball (the face extrapolated
        // would have read the ball below it as pressed in).
        assert!(approach(Vector2::new(1.2, -0.01)) < -0.1);
        // Below the beam, the lower face.
        let under = approach(Vector2::new(0.5, -(0.0025 + 0.005 - 2e-6)));
        assert!((under - 2e-6).abs() < 1e-15, "{under:e}");
    }
}
