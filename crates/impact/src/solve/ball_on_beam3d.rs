//! The ball on the 3D geometrically exact beam as one [`hht::Model`]: Simo's rod (six unknowns a
//! node: displacement and material rotation increment), the ball centre's three, and the
//! contact force between them. What an off-centre strike needs: the contact force's moment
//! about the beam's axis twists the beam, and the twist moves the struck face under the ball.
//!
//! **Model.** The beam lies along x from the first support, its width along y (E2) and its
//! thickness along z (E3); the ball, a rigid sphere of mass m, starts at first touch above the
//! top face at (impact point, offset, h/2 + R) and moves along -z. Gravity acts on the ball only.
//!
//! **Contact.** Frictionless, as the planar model ([`super::ball_on_beam`]): the contact
//! element is the one whose chord passes nearest to the ball centre c, the projection on it is
//! `xi = (c - x_a).t / t.t`, the face normal the interpolated section axis
//! `n = normalise((1 - xi) Lambda_a E3 + xi Lambda_b E3)`, and the approach
//!
//! `delta = R + h/2 - |(c - x).n|`, `x = x_a + xi t`.
//!
//! The face is a plane through the centre line's point offset by h/2 along n: the ball's
//! offset across the width enters through c, so a twist theta about the axis tilts the face
//! under the ball and moves it by offset x theta (to first order), which is the coupling of the
//! modal method's torsion modes. Past an end of the beam the ball meets the end's edge, the
//! line through `x_end +- (h/2) Lambda E3` along `Lambda E2`, and `delta = R - dist(c, line)`.
//! The face's side edges are not modelled (the plan warns where the patch reaches them).
//!
//! The generalised force is `F grad(delta)` over the 15 unknowns it touches (ball, and the
//! displacement and rotation increment of both nodes), its Newton matrix
//! `k grad grad^T + F Hess(delta)` (+ the damping term), by second-order forward
//! differentiation (num-dual) of the formula above with each node's rotation
//! `Lambda exp(theta^)` expanded to second order, `Lambda (I + theta^ + theta^2/2)`: the
//! derivatives at theta = 0, which are all Newton needs, are exact.

use faer::{ColMut, ColRef};
use hertz::ContactLaw;
use hht::{Band, Model, NewtonWeights, Triplets};
use nalgebra::{Matrix3, SVector, UnitQuaternion, Vector3};
use num_dual::Dual2SVec64;
use simo_beam::{BeamModel, BeamState};
use std::cell::{Cell, RefCell};

use super::ball_on_beam::{ContactPoint, FaceTerms, Order, STICKY_REACH};
use super::struck::OutOfPlane;

/// Configuration of the coupled model: the beam's and the ball centre's (m).
#[derive(Debug, Clone)]
pub struct BallOnBeam3dConfig {
    /// The beam.
    pub beam: BeamState,
    /// Ball centre (x, y, z) (m).
    pub ball: Vector3<f64>,
}

/// The y and z of the section's width axis E2 turned by its rotation `r` from its reference
/// `frame`, in that frame (its twist turns it from (0, 1, 0) toward (0, 0, 1)): the rotation
/// matrix's entries (1, 1) and (2, 1) of the relative quaternion (w, i, j, k),
/// 1 - 2 (i^2 + k^2) and 2 (j k + w i).
fn turned_width_axis(frame: &UnitQuaternion<f64>, r: &UnitQuaternion<f64>) -> (f64, f64) {
    let relative = frame.conjugate() * r;
    let (w, i, j, k) = (relative.w, relative.i, relative.j, relative.k);
    (1.0 - 2.0 * (i * i + k * k), 2.0 * (j * k + w * i))
}

/// The node whose section is twisted most (the last of equals), if its rank is above `floor`
/// (`None` otherwise, or without nodes): the largest [`pseudo_angle`] of the width axis
/// [`turned_width_axis`] of `rotations` from their reference `frames`, the same numbers by the
/// same operations, a block of nodes at a time in plain arithmetic that the vector lanes run
/// (node by node through nalgebra's quaternions it took 3.5 % of a 3D run: every accepted step
/// asks). A block's largest rank is taken without branches, and its node looked for only where
/// it is above the floor and the blocks' before (a node at a time, the ranks' comparisons took
/// 1 % of the run).
pub(crate) fn most_twisted_node(
    frames: &[UnitQuaternion<f64>],
    rotations: &[UnitQuaternion<f64>],
    floor: f64,
) -> Option<usize> {
    hht::fast::run(MostTwisted { frames, rotations, floor })
}

/// [`most_twisted_node`] as a [`hht::fast::Kernel`].
struct MostTwisted<'a> {
    frames: &'a [UnitQuaternion<f64>],
    rotations: &'a [UnitQuaternion<f64>],
    floor: f64,
}

impl hht::fast::Kernel for MostTwisted<'_> {
    type Output = Option<usize>;

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) -> Option<usize> {
        const BLOCK: usize = 64;
        let mut ranks = [0.0; BLOCK];
        let mut best: Option<(usize, f64)> = None;
        let blocks = self.frames.chunks(BLOCK).zip(self.rotations.chunks(BLOCK));
        for (b, (frames, rotations)) in blocks.enumerate() {
            for ((rank, f), r) in ranks.iter_mut().zip(frames).zip(rotations) {
                // conj(f) r as nalgebra's product (i, j, k, w), to the bit, and the axis.
                let (f, r) = (&f.coords, &r.coords);
                let s = [-f[0], -f[1], -f[2], f[3]];
                let w = s[3] * r[3] - s[0] * r[0] - s[1] * r[1] - s[2] * r[2];
                let i = s[3] * r[0] + s[0] * r[3] + s[1] * r[2] - s[2] * r[1];
                let j = s[3] * r[1] - s[0] * r[2] + s[1] * r[3] + s[2] * r[0];
                let k = s[3] * r[2] + s[0] * r[1] - s[1] * r[0] + s[2] * r[3];
                *rank = pseudo_angle((1.0 - 2.0 * (i * i + k * k), 2.0 * (j * k + w * i)));
            }
            let ranks = &ranks[..frames.len()];
            // (The ranks are not negative: their largest magnitude is their largest.)
            let largest = hht::fast::largest_magnitude(ranks);
            if largest > self.floor && best.is_none_or(|b| largest >= b.1) {
                let k = ranks.iter().rposition(|&r| r >= largest).unwrap_or(0);
                best = Some((b * BLOCK + k, largest));
            }
        }
        best.map(|(node, _)| node)
    }
}

/// A number that grows with the size of the twist `atan2(z, y)` of a width axis turned to
/// `(y, z)` over [0, pi] (a pseudo-angle: `|z| / (|y| + |z|)`, and 2 less that past a right
/// angle; near zero it is the angle to relative round-off; an axis turned onto E1 ranks 0, as
/// atan2(0, 0)), to rank the nodes without an arc tangent each. Both sides of each choice
/// computed, then chosen (no branches in a block loop).
#[inline(always)]
fn pseudo_angle((y, z): (f64, f64)) -> f64 {
    let size = y.abs() + z.abs();
    let share = z.abs() / size;
    let turned = if y > 0.0 { share } else { 2.0 - share };
    if size == 0.0 {
        0.0
    } else {
        turned
    }
}

/// Unknowns of one contact element: ball (3), node a (6), node b (6).
const LOCAL: usize = 15;

/// The contact kinematics at a configuration, over the 15 local unknowns.
type ContactPoint3d = ContactPoint<LOCAL>;

/// The coupled ball-beam-contact model in 3D for [`hht`].
pub struct BallOnBeam3d<'a, L: ContactLaw> {
    beam: BeamModel,
    nb: usize,
    mass: f64,
    gravity: f64,
    radius: f64,
    half_thickness: f64,
    /// The strike's offset across the width (m): where the face's motion is read.
    offset: f64,
    /// Against the ball's velocity (unit): the direction the struck face's height is read
    /// along (+z on a `[beam]`).
    up: Vector3<f64>,
    /// The faces struck.
    face: Face,
    pub(crate) law: &'a L,
    /// The law's history, committed after every accepted step.
    pub law_state: L::State,
    /// Global equation numbers of each element's 15 local unknowns.
    local_dofs: Vec<[Option<usize>; LOCAL]>,
    /// The contact element of the last accepted step (as the planar model's).
    sticky_element: Option<usize>,
    /// Every element end whose frame is its node's turned by a corner offset (element, end):
    /// where a section's twist about its own member's axis is not the node's reading.
    corner_ends: Vec<(usize, usize)>,
    /// Per element, which of the struck faces' pair faces the ball: +1 where the face on the
    /// + side of its normal axis (E3, or E2 on a width face) does, -1 where the - side's does.
    sides: Vec<f64>,
    /// Per element, the strain energy's weights of the squares of its struck face's strains
    /// ([`struck_strains`]'s order): `l0 / 2` times the section's stiffness for each.
    energy_weights: Vec<[f64; 6]>,
    /// Every element's strains (Gamma1..3, K1..3, an array each, padded past the last element
    /// to whole blocks of the element pass: read them zipped with the elements) at the last
    /// net force, from the same pass, and how many net forces have been evaluated (see
    /// [`super::struck::Struck::force_passes`]).
    last_strains: RefCell<[Vec<f64>; 6]>,
    force_passes: Cell<u64>,
    /// The last contact point computed, with its element and the 17 numbers it was computed
    /// from (ball centre, the element's nodes' positions and quaternions), as the planar
    /// model's: a step asks for the same one several times (the converged residual, the
    /// step's acceptance, the approach's rate).
    last_contact: RefCell<Option<Memo>>,
}

/// A contact point with what it was computed from: the element, the 17 numbers, the order.
type Memo = (usize, [f64; 17], Order, ContactPoint3d);

/// The node's position and rotation matrix.
type Node = (Vector3<f64>, Matrix3<f64>);

/// Which faces of the rectangle the ball strikes: those normal to the section's E3 (the
/// thickness faces, a `[beam]`'s) or to its E2 (the width faces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Face {
    /// Normal +-E3, `thickness/2` from the centre line, the offset along E2.
    Thickness,
    /// Normal +-E2, `width/2` from the centre line, the offset along E3.
    Width,
}

impl Face {
    /// The section axes (columns of the rotation) of the face's normal and of the offset.
    pub(crate) fn axes(self) -> (usize, usize) {
        match self {
            Face::Thickness => (2, 1),
            Face::Width => (1, 2),
        }
    }

    /// How a twist theta moves the face's point at the offset e along its normal: +e theta on
    /// a thickness face (E2 turns toward E3), -e theta on a width face (E3 turns toward -E2).
    pub(crate) fn twist_sign(self) -> f64 {
        match self {
            Face::Thickness => 1.0,
            Face::Width => -1.0,
        }
    }
}

/// [`BallOnBeam3d::facing`] of `beam` struck against `face` along `-up`.
fn facing(beam: &BeamModel, (up, face): (Vector3<f64>, Face), e: usize) -> f64 {
    let element = &beam.mesh().elements[e];
    let (normal, _) = face.axes();
    // The element's own end frame (at a corner its node's is the other member's).
    let frame = beam.mesh().frames[element.nodes[0]] * element.offsets[0];
    let n = frame.to_rotation_matrix().into_inner().column(normal).into_owned();
    let side = if n.dot(&up) < 0.0 { -1.0 } else { 1.0 };
    side * face.twist_sign()
}

/// Which of `face`'s pair element `e` of `beam` meets the ball moving along `-up`: +1 where
/// the face on the + side of its normal axis (E3, or E2 on a width face) does, else -1.
pub(crate) fn struck_side(beam: &BeamModel, (up, face): (Vector3<f64>, Face), e: usize) -> f64 {
    facing(beam, (up, face), e) * face.twist_sign()
}

/// A section's strains (Gamma1..3, K1..3) as the struck `face` sees them, `side` its pair's
/// face the ball meets ([`struck_side`]): the planar beam's (extension, shear along the
/// strike, bending curvature) and out of its plane (the lateral curvature, the twist rate,
/// the other shear), so that the face's outer fibre strain is extension - (depth/2)
/// curvature. On a thickness face whose + side (along E3)
/// is struck, (Gamma1, Gamma3, -K2) (the fibre at z = t/2 strains by Gamma1 + z K2) and
/// (K3, K1, Gamma2); on a width face (the fibre at y = w/2 strains by Gamma1 - y K3),
/// (Gamma1, Gamma2, K3) and (K2, K1, Gamma3); the - side's negate the curvature.
#[inline(always)]
pub(crate) fn struck_strains(
    face: Face,
    side: f64,
    [g0, g1, g2, k0, k1, k2]: [f64; 6],
) -> ((f64, f64, f64), OutOfPlane) {
    match face {
        Face::Thickness => ((g0, g2, -side * k1), (k2, k0, g1)),
        Face::Width => ((g0, g1, side * k2), (k1, k0, g2)),
    }
}

/// The unknowns and weights whose sum is the struck face's height along `up` at `(i, xi)`
/// (element, local coordinate) of `beam`, `offset` (m) across the face: the two nodes'
/// translations along `up`, interpolated linearly, and their rotations about the section axis
/// times the offset (small rotation; the rotation unknowns are material, about E1).
pub(crate) fn face_rows(
    beam: &BeamModel,
    (up, face, offset): (Vector3<f64>, Face, f64),
    (i, xi): (usize, f64),
) -> Vec<(usize, f64)> {
    let e = offset * facing(beam, (up, face), i);
    // The twist is about the element's axis, its end frames' E1 in the node's axes (E1 but at
    // a corner's node).
    let element = &beam.mesh().elements[i];
    let axis = |end: usize| element.offsets[end] * Vector3::x();
    let nodes = element.nodes;
    [(nodes[0], 1.0 - xi, axis(0)), (nodes[1], xi, axis(1))]
        .into_iter()
        .flat_map(|(node, w, ax)| {
            let turn = (0..3).map(move |k| (node, 3 + k, e * w * ax[k]));
            [(node, 0, w * up.x), (node, 1, w * up.y), (node, 2, w * up.z)].into_iter().chain(turn)
        })
        .filter(|(_, _, w)| *w != 0.0)
        .filter_map(|(node, k, w)| beam.dof(node, k).map(|d| (d, w)))
        .collect()
}

/// The approach for local unknowns `u` added to the configuration (`c0` the ball, `a` and `b`
/// the element's nodes); `ends` says whether the element's nodes are the beam's first and last.
#[cfg(test)]
fn approach_of<T: nalgebra::RealField + Copy>(
    u: &SVector<T, LOCAL>,
    c0: &Vector3<f64>,
    a: &Node,
    b: &Node,
    surface: (f64, f64, Face),
    ends: (bool, bool),
) -> T {
    approach_turned(u, c0, (a, b, None), surface, ends)
}

/// The element's end frames' turns from their nodes' (`Lambda_end = Lambda_node O`, the
/// element's `offsets`: at a corner the end frames are the member's, the node's the other
/// member's), as matrices.
type Turns = (Matrix3<f64>, Matrix3<f64>);

/// [`approach_of`] on an element whose end frames are turned from their nodes' by `turns`
/// (`None`: not turned), with `a.1` and `b.1` the end frames: a node's rotation increment
/// theta (material, at the node) turns its end frame by `O^T theta` in the end frame's axes
/// (`Lambda exp(theta^) O = Lambda O exp((O^T theta)^)`).
fn approach_turned<T: nalgebra::RealField + Copy>(
    u: &SVector<T, LOCAL>,
    c0: &Vector3<f64>,
    (a, b, turns): (&Node, &Node, Option<&Turns>),
    (radius, half, face): (f64, f64, Face),
    ends: (bool, bool),
) -> T {
    let (normal, across) = face.axes();
    let lift = nalgebra::convert::<f64, T>;
    let part = |k: usize| Vector3::new(u[k], u[k + 1], u[k + 2]);
    let turn = |o: &Matrix3<f64>, k: usize| o.map(lift).transpose() * part(k);
    let (theta_a, theta_b) = match turns {
        Some((oa, ob)) => (turn(oa, 6), turn(ob, 12)),
        None => (part(6), part(12)),
    };
    let c = c0.map(lift) + part(0);
    let xa = a.0.map(lift) + part(3);
    let xb = b.0.map(lift) + part(9);
    // A node's section axes `normal` and `across` turned by its rotation increment theta to
    // second order: R (I + theta^ + theta^2 / 2) e_k = R (e_k + theta x e_k + theta x (theta x
    // e_k) / 2), by cross products (in the derivatives' dual numbers, fewer products than
    // through 3x3 matrices).
    let turned = |r: &Matrix3<f64>, theta: Vector3<T>| {
        let axis = |k: usize| {
            let e = Vector3::from_fn(|i, _| if i == k { T::one() } else { T::zero() });
            let te = theta.cross(&e);
            let local = e + te + theta.cross(&te) * lift(0.5);
            r.map(lift) * local
        };
        (axis(normal), axis(across))
    };
    let (ra, rb) = (turned(&a.1, theta_a), turned(&b.1, theta_b));
    let (radius, half) = (lift(radius), lift(half));
    let t = xb - xa;
    let xi = (c - xa).dot(&t) / t.dot(&t);
    let edge = |x: Vector3<T>, (n, along): &(Vector3<T>, Vector3<T>)| {
        let (n, along) = (*n, *along);
        let side = if (c - x).dot(&n) < T::zero() { -half } else { half };
        let v = c - (x + n * side);
        let across = v - along * v.dot(&along);
        radius - across.norm()
    };
    if ends.0 && xi < T::zero() {
        return edge(xa, &ra);
    }
    if ends.1 && xi > T::one() {
        return edge(xb, &rb);
    }
    let x = xa + t * xi;
    let d = ra.0 * (T::one() - xi) + rb.0 * xi;
    let n = d / d.norm();
    radius + half - (c - x).dot(&n).abs()
}

/// The approach at zero increments and its gradient over the local unknowns, by the
/// derivatives of [`approach_of`]'s formulas written out (one pass; in dual numbers it took
/// one pass an unknown, 6 % of a 3D run). A rotation increment theta turns a node's section
/// axis `R e` by `R (theta x e)`, so `v . R (theta x e) = theta . (e x R^T v)`.
///
/// On the face, `delta = R + h/2 - |g|` by [`FaceTerms`] with the normals `R_a e_n`, `R_b e_n`,
/// whose turns `dd = (1 - xi) R_a (theta_a x e_n) + ...` give `p.dd` in the rotations.
///
/// Past an end, `v = c - (x_e + s R_e e_n)` (s = +-h/2, the side), `w = v - a (v.a)` with
/// `a = R_e e_across` and `delta = R - |w|`: as `w` is normal to `a`,
/// `d|w| = w^.(dc - dx_e) - s theta.(e_n x R^T w^) - (v.a) theta.(e_a x R^T w^)`.
///
/// With end frames turned from their nodes' (`turns`, see [`approach_turned`]), the gradient
/// over the end frames' increments `O^T theta` is turned back onto the nodes' by `O`.
fn approach_gradient_turned(
    c: &Vector3<f64>,
    (a, b, turns): (&Node, &Node, Option<&Turns>),
    surface: (f64, f64, Face),
    ends: (bool, bool),
) -> (f64, SVector<f64, LOCAL>) {
    let (delta, mut gradient) = approach_gradient(c, a, b, surface, ends);
    if let Some((oa, ob)) = turns {
        for (at, o) in [(6, oa), (12, ob)] {
            let turned = o * gradient.fixed_rows::<3>(at);
            gradient.fixed_rows_mut::<3>(at).copy_from(&turned);
        }
    }
    (delta, gradient)
}

/// [`approach_gradient_turned`] of an element whose end frames are its nodes'.
fn approach_gradient(
    c: &Vector3<f64>,
    a: &Node,
    b: &Node,
    (radius, half, face): (f64, f64, Face),
    ends: (bool, bool),
) -> (f64, SVector<f64, LOCAL>) {
    let (normal, across) = face.axes();
    let unit = |k: usize| Vector3::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
    let (e_n, e_a) = (unit(normal), unit(across));
    let mut gradient = SVector::<f64, LOCAL>::zeros();
    let mut put = |at: usize, v: Vector3<f64>| gradient.fixed_rows_mut::<3>(at).copy_from(&v);
    let t = b.0 - a.0;
    let xi = (c - a.0).dot(&t) / t.dot(&t);
    // Past an end: the edge of the end node's face (`at`: its place among the unknowns).
    let past = match ends {
        (true, _) if xi < 0.0 => Some((a, 3)),
        (_, true) if xi > 1.0 => Some((b, 9)),
        _ => None,
    };
    if let Some(((x, r), at)) = past {
        let (n, along) = (r.column(normal).into_owned(), r.column(across).into_owned());
        let side = if (c - x).dot(&n) < 0.0 { -half } else { half };
        let v = c - (x + n * side);
        let va = v.dot(&along);
        let w = v - along * va;
        let size = w.norm();
        let unit_w = w / size;
        let local = r.transpose() * unit_w;
        put(0, -unit_w);
        put(at, unit_w);
        put(at + 3, e_n.cross(&local) * side + e_a.cross(&local) * va);
        return (radius - size, gradient);
    }
    let (na, nb) = (a.1.column(normal).into_owned(), b.1.column(normal).into_owned());
    let f = FaceTerms::new(c, (&a.0, &b.0), (&na, &nb));
    // The gradient of g, then of delta = R + h/2 - |g|.
    let sign = if f.g < 0.0 { 1.0 } else { -1.0 };
    put(0, f.dc * sign);
    put(3, f.da * sign);
    put(6, e_n.cross(&(a.1.transpose() * f.p)) * ((1.0 - f.xi) * sign));
    put(9, f.db * sign);
    put(12, e_n.cross(&(b.1.transpose() * f.p)) * (f.xi * sign));
    (radius + half - f.g.abs(), gradient)
}

impl<'a, L: ContactLaw> BallOnBeam3d<'a, L> {
    /// The coupled model: `beam` (straight along x, thickness along z), a ball of `mass` (kg)
    /// and `radius` (m) under `gravity` (m/s^2, along -z) striking `offset` (m) off the
    /// centreline, a struck face `half_thickness` (m) above the centre line, and `law`.
    pub fn new(
        beam: BeamModel,
        (mass, gravity, radius): (f64, f64, f64),
        offset: f64,
        half_thickness: f64,
        law: &'a L,
    ) -> Self {
        let struck = (offset, Vector3::z(), Face::Thickness);
        Self::striking(beam, (mass, gravity, radius), struck, half_thickness, law)
    }

    /// [`BallOnBeam3d::new`] for a ball moving along `-up` against `face` (a `[structure]`),
    /// `half_depth` (m) from the centre line; gravity acts along the ball's velocity.
    pub fn striking(
        beam: BeamModel,
        (mass, gravity, radius): (f64, f64, f64),
        (offset, up, face): (f64, Vector3<f64>, Face),
        half_thickness: f64,
        law: &'a L,
    ) -> Self {
        let nb = hht::Model::ndof(&beam);
        let local_dofs = beam
            .mesh()
            .elements
            .iter()
            .map(|e| {
                let mut d = [None; LOCAL];
                for (k, slot) in d[..3].iter_mut().enumerate() {
                    *slot = Some(nb + k);
                }
                for (end, node) in e.nodes.into_iter().enumerate() {
                    for k in 0..6 {
                        d[3 + 6 * end + k] = beam.dof(node, k);
                    }
                }
                d
            })
            .collect();
        let corner_ends = beam
            .mesh()
            .elements
            .iter()
            .enumerate()
            .filter(|(_, e)| !e.straight())
            .flat_map(|(k, _)| [(k, 0), (k, 1)])
            .collect();
        let up = up.normalize();
        let sides =
            (0..beam.mesh().elements.len()).map(|e| struck_side(&beam, (up, face), e)).collect();
        // Each element's `l0 / 2` times its EA, GA2, GA3, GJ, EI2, EI3 in the order of the
        // struck face's strains (the order alone: the signs are the side's; `struck_strains`
        // is a signed permutation of the strains, and a test holds the energy to the
        // elements' own).
        let energy_weights = beam
            .mesh()
            .elements
            .iter()
            .map(|e| {
                let c = &e.section;
                let w = [c.ea, c.ga2, c.ga3, c.gj, c.ei2, c.ei3].map(|c| 0.5 * e.length * c);
                let ((a, b, c), (d, f, g)) = struck_strains(face, 1.0, w);
                [a, b, c, d, f, g].map(f64::abs)
            })
            .collect();
        Self {
            corner_ends,
            sides,
            energy_weights,
            beam,
            nb,
            mass,
            gravity,
            radius,
            half_thickness,
            offset,
            up,
            face,
            law,
            law_state: L::State::default(),
            local_dofs,
            sticky_element: None,
            last_strains: RefCell::default(),
            force_passes: Cell::new(0),
            last_contact: RefCell::new(None),
        }
    }

    /// How many net forces have been evaluated (see
    /// [`super::struck::Struck::force_passes`]).
    pub(crate) fn force_passes(&self) -> u64 {
        self.force_passes.get()
    }

    /// Every element's strains at the configuration of the last net force, from that pass, as
    /// the struck face's ([`struck_strains`]) into `out` and `out_of_plane` (`false`, and
    /// nothing written, before any pass).
    pub(crate) fn last_pass_strains(
        &self,
        out: &mut [(f64, f64, f64)],
        out_of_plane: &mut [OutOfPlane],
    ) -> bool {
        let last = self.last_strains.borrow();
        let [g0, g1, g2, k0, k1, k2] = &*last;
        // Zipped, not indexed: a loop without bounds checks (element by element through a
        // callback, 1 % of the paper's tip in 3D).
        let each = out.iter_mut().zip(out_of_plane.iter_mut()).zip(&self.sides);
        let strains = g0.iter().zip(g1).zip(g2).zip(k0).zip(k1).zip(k2);
        for (((o, p), side), (((((g0, g1), g2), k0), k1), k2)) in each.zip(strains) {
            (*o, *p) = struck_strains(self.face, *side, [*g0, *g1, *g2, *k0, *k1, *k2]);
        }
        !g0.is_empty()
    }

    /// The beam model.
    pub fn beam(&self) -> &BeamModel {
        &self.beam
    }

    /// The strike's offset across the width (m).
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// Against the ball's velocity (unit).
    pub fn up(&self) -> Vector3<f64> {
        self.up
    }

    /// The faces struck.
    pub fn face(&self) -> Face {
        self.face
    }

    /// How a twist moves the struck point along `up`, per unit offset and twist: the face's
    /// sign (see [`Face::twist_sign`]) times +1 where its normal (of element `e`'s first node at
    /// rest) points along `up`, -1 where against it.
    pub(crate) fn facing(&self, e: usize) -> f64 {
        facing(&self.beam, (self.up, self.face), e)
    }

    /// Per element, which of the struck faces' pair meets the ball ([`struck_side`]).
    pub(crate) fn sides(&self) -> &[f64] {
        &self.sides
    }

    /// Per element, its strain energy's weights of its struck strains' squares.
    pub(crate) fn energy_weights(&self) -> &[[f64; 6]] {
        &self.energy_weights
    }

    /// Node `node`'s section rotation about its axis from its reference frame (rad): the
    /// angle that turns E2 toward E3, of the rotation from the reference.
    pub(crate) fn node_twist(&self, q: &BallOnBeam3dConfig, node: usize) -> f64 {
        let (y, z) = turned_width_axis(&self.beam.mesh().frames[node], &q.beam.rotations[node]);
        z.atan2(y)
    }

    /// Element `e`'s section at its end `end` (0 or 1): its rotation about the element's own
    /// axis from its reference (rad), as [`Self::node_twist`] but in the element's end frame
    /// (at a corner the node's frame is the other member's, and so is its axis).
    pub(crate) fn end_twist(&self, q: &BallOnBeam3dConfig, e: usize, end: usize) -> f64 {
        let element = &self.beam.mesh().elements[e];
        let node = element.nodes[end];
        if element.straight() {
            return self.node_twist(q, node);
        }
        let o = element.offsets[end];
        let frame = self.beam.mesh().frames[node] * o;
        let (y, z) = turned_width_axis(&frame, &(q.beam.rotations[node] * o));
        z.atan2(y)
    }

    /// The node whose section is twisted most about its own member's axis, and the twist's
    /// size (rad): every node about its own frame's axis, and at a corner also the other
    /// member's end section about that member's axis ([`Self::end_twist`]).
    pub(crate) fn largest_twist(
        &self,
        q: &BallOnBeam3dConfig,
        beyond: f64,
    ) -> Option<(usize, f64)> {
        // Ranked without an arc tangent a node (every accepted step asks): one for the node,
        // and none where no node's rank is above the rank of a twist `beyond`.
        // (The rank of `beyond` through its cosine and sine, lowered by a margin: it may round
        // above the rank of a node's twist that is larger by an ulp; the last test is exact.)
        let floor = if beyond >= 0.0 {
            pseudo_angle((beyond.cos(), beyond.sin())) * (1.0 - 1e-12)
        } else {
            -1.0
        };
        let frames = &self.beam.mesh().frames;
        let node = most_twisted_node(frames, &q.beam.rotations, floor)
            .map(|node| (node, self.node_twist(q, node).abs()));
        let ends = self.corner_ends.iter().map(|&(e, end)| {
            (self.beam.mesh().elements[e].nodes[end], self.end_twist(q, e, end).abs())
        });
        let largest = node.into_iter().chain(ends).fold(None, |a: Option<(usize, f64)>, b| {
            if a.is_none_or(|a| b.1 > a.1) {
                Some(b)
            } else {
                a
            }
        })?;
        (largest.1 > beyond).then_some(largest)
    }

    /// Keeps the contact element of configuration `q` (an accepted step) for the next steps.
    pub fn commit_contact_element(&mut self, q: &BallOnBeam3dConfig) {
        self.sticky_element = Some(self.nearest_element(q).0);
    }

    fn elements(&self) -> usize {
        self.beam.mesh().elements.len()
    }

    /// Chord of element `e`: its first node and the vector to its second (m).
    fn chord(&self, q: &BeamState, e: usize) -> (Vector3<f64>, Vector3<f64>) {
        let [a, b] = self.beam.mesh().elements[e].nodes;
        (q.positions[a], q.positions[b] - q.positions[a])
    }

    /// The contact element and the clamped projection on it (as the planar model's).
    fn nearest_element(&self, q: &BallOnBeam3dConfig) -> (usize, f64) {
        if let Some(i) = self.sticky_element {
            let (xa, t) = self.chord(&q.beam, i);
            let xi = (q.ball - xa).dot(&t) / t.dot(&t);
            if (-STICKY_REACH..=1.0 + STICKY_REACH).contains(&xi) {
                return (i, xi.clamp(0.0, 1.0));
            }
        }
        let mut best = (0, 0.0, f64::INFINITY);
        for i in 0..self.elements() {
            let (xa, t) = self.chord(&q.beam, i);
            let xi = ((q.ball - xa).dot(&t) / t.dot(&t)).clamp(0.0, 1.0);
            // The distance across the width counts as along the thickness: the chord lies on
            // the centre line, and an offset ball is as near its element as a centred one.
            let distance = (q.ball - (xa + t * xi)).norm();
            if distance < best.2 {
                best = (i, xi, distance);
            }
        }
        (best.0, best.1)
    }

    /// Approach only (no derivatives).
    pub(crate) fn approach(&self, q: &BallOnBeam3dConfig) -> f64 {
        self.contact_point(q, Order::Value).delta
    }

    /// The contact point with derivatives up to `order` (the others left zero).
    pub(crate) fn contact_point(&self, q: &BallOnBeam3dConfig, order: Order) -> ContactPoint3d {
        let (element, xi) = self.nearest_element(q);
        let [na, nb] = self.beam.mesh().elements[element].nodes;
        let (positions, rotations) = (&q.beam.positions, &q.beam.rotations);
        let key: [f64; 17] = std::array::from_fn(|k| match k {
            0..3 => q.ball[k],
            3..6 => positions[na][k - 3],
            6..10 => rotations[na].coords[k - 6],
            10..13 => positions[nb][k - 10],
            _ => rotations[nb].coords[k - 13],
        });
        if let Some((e, k, o, p)) = &*self.last_contact.borrow() {
            let same = *e == element && k.iter().zip(&key).all(|(a, b)| a.to_bits() == b.to_bits());
            if same && *o >= order {
                return p.clone();
            }
        }
        let p = self.compute_contact_point(q, order, (element, xi), (na, nb));
        *self.last_contact.borrow_mut() = Some((element, key, order, p.clone()));
        p
    }

    /// [`BallOnBeam3d::contact_point`] on `element` at `xi`, its nodes being `na` and `nb`.
    fn compute_contact_point(
        &self,
        q: &BallOnBeam3dConfig,
        order: Order,
        (element, xi): (usize, f64),
        (na, nb): (usize, usize),
    ) -> ContactPoint3d {
        // The element's end frames (its nodes' turned by its offsets at a corner).
        let e = &self.beam.mesh().elements[element];
        let straight = e.straight();
        let node = |i: usize, end: usize| -> Node {
            let r =
                if straight { q.beam.rotations[i] } else { q.beam.rotations[i] * e.offsets[end] };
            (q.beam.positions[i], r.to_rotation_matrix().into_inner())
        };
        let (a, b) = (node(na, 0), node(nb, 1));
        let turns: Option<Turns> = (!straight)
            .then(|| e.offsets.map(|o| o.to_rotation_matrix().into_inner()))
            .map(|[oa, ob]| (oa, ob));
        let turns = turns.as_ref();
        let surface = (self.radius, self.half_thickness, self.face);
        let ends = (element == 0, element + 1 == self.elements());
        let c = &q.ball;
        let zero = SVector::<f64, LOCAL>::zeros();
        let (delta, gradient, hessian) = match order {
            Order::Value => {
                (approach_turned(&zero, c, (&a, &b, turns), surface, ends), SVector::zeros(), None)
            }
            Order::Gradient => {
                let (delta, gradient) = approach_gradient_turned(c, (&a, &b, turns), surface, ends);
                (delta, gradient, None)
            }
            Order::Hessian => {
                let (d, g, h) = num_dual::hessian(
                    |u: SVector<Dual2SVec64<LOCAL>, LOCAL>| {
                        approach_turned(&u, c, (&a, &b, turns), surface, ends)
                    },
                    &zero,
                );
                (d, g, Some(Box::new(h)))
            }
        };
        ContactPoint3d { element, xi, delta, gradient, hessian }
    }

    /// The contact point with its derivatives if the ball touches (`None` otherwise).
    fn touching(&self, q: &BallOnBeam3dConfig, order: Order) -> Option<ContactPoint3d> {
        let release = self.law.release_approach(&self.law_state);
        // In contact (the last point computed touched), the derivatives at once: the value
        // first and then the point again with them cost two evaluations a pass in contact.
        // (The value evaluated with them is the same bits as alone: a test holds it.)
        let was = self.last_contact.borrow().as_ref().is_some_and(|(.., p)| p.delta > release);
        let p = self.contact_point(q, if was { order } else { Order::Value });
        (p.delta > release).then(|| if was { p } else { self.contact_point(q, order) })
    }

    /// delta-dot = grad(delta) . local velocities.
    fn rate(&self, p: &ContactPoint3d, v: ColRef<'_, f64>) -> f64 {
        p.rate(&self.local_dofs[p.element], v)
    }

    /// Contact approach, its rate and the law's force at a state.
    pub(crate) fn contact(
        &self,
        q: &BallOnBeam3dConfig,
        v: ColRef<'_, f64>,
    ) -> (f64, f64, hertz::ContactForce) {
        let p = self.contact_point(q, Order::Gradient);
        let rate = self.rate(&p, v);
        (p.delta, rate, self.law.force(&self.law_state, p.delta, rate))
    }

    fn ball(&self, x: ColRef<'_, f64>) -> Vector3<f64> {
        Vector3::new(x[self.nb], x[self.nb + 1], x[self.nb + 2])
    }

    /// The Newton matrix's terms of the ball: its mass and, in contact, the contact's block.
    fn ball_tangent(
        &self,
        q: &BallOnBeam3dConfig,
        v: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let nb = self.nb;
        for k in 0..3 {
            out.push(nb + k, nb + k, w.inertia * w.da * self.mass);
        }
        let Some(p) = self.touching(q, Order::Hessian) else {
            return;
        };
        let cf = self.law.force(&self.law_state, p.delta, self.rate(&p, v));
        p.push_block(&self.local_dofs[p.element], &cf, w, out);
    }
}

impl<L: ContactLaw> Model for BallOnBeam3d<'_, L> {
    type Config = BallOnBeam3dConfig;

    fn ndof(&self) -> usize {
        self.nb + 3
    }

    fn update(&self, q: &mut BallOnBeam3dConfig, dq: ColRef<'_, f64>) {
        self.beam.update(&mut q.beam, dq.subrows(0, self.nb));
        q.ball += self.ball(dq);
    }

    fn displaced(&self, q: &BallOnBeam3dConfig, dq: ColRef<'_, f64>, out: &mut BallOnBeam3dConfig) {
        self.beam.displaced(&q.beam, dq.subrows(0, self.nb), &mut out.beam);
        out.ball = q.ball + self.ball(dq);
    }

    fn inertial_force(
        &self,
        q: &BallOnBeam3dConfig,
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

    fn predicted_inertial_force(
        &self,
        q: &BallOnBeam3dConfig,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        old: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
        let nb = self.nb;
        debug_assert_eq!(old.nrows(), nb + 3, "the old inertial force, one row an unknown");
        // The beam's (its rotations' rows anew), then the ball's m a, at the same a: `old`'s.
        self.beam.predicted_inertial_force(
            &q.beam,
            v.subrows(0, nb),
            a.subrows(0, nb),
            old.subrows(0, nb),
            out.as_mut().subrows_mut(0, nb),
        );
        for k in 0..3 {
            out[nb + k] = old[nb + k];
        }
    }

    fn net_force(
        &self,
        t: f64,
        q: &BallOnBeam3dConfig,
        v: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
        let nb = self.nb;
        // The pass's strains kept: an accepted state is its step's last iterate, whose strains
        // then need no pass of their own.
        let mut strains = self.last_strains.borrow_mut();
        self.beam.net_force_and_strains(t, &q.beam, out.as_mut().subrows_mut(0, nb), &mut strains);
        drop(strains);
        self.force_passes.set(self.force_passes.get() + 1);
        // Gravity pulls the ball along -up: net force = -(external) = +m g up.
        for k in 0..3 {
            out[nb + k] = self.mass * self.gravity * self.up[k];
        }
        let Some(p) = self.touching(q, Order::Gradient) else {
            return;
        };
        let f = self.law.force(&self.law_state, p.delta, self.rate(&p, v)).force;
        p.add_force(&self.local_dofs[p.element], f, out);
    }

    fn tangent(
        &self,
        t: f64,
        q: &BallOnBeam3dConfig,
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
        q: &BallOnBeam3dConfig,
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

    fn force_scale(&self, q: &BallOnBeam3dConfig) -> f64 {
        self.beam.force_scale(&q.beam)
    }

    fn configuration_scale(&self, q: &BallOnBeam3dConfig) -> f64 {
        self.beam.configuration_scale(&q.beam).max(q.ball.amax())
    }

    /// The ball's rows: its inertia is a round-off of the beam's forces for a small ball.
    fn own_balance_rows(&self) -> std::ops::Range<usize> {
        let n = self.ndof();
        n - 3..n
    }

    /// Node-major unknowns, six a node, elements between neighbours: banded with half-bandwidth
    /// 11, the ball's three unknowns the dense border.
    fn band(&self) -> Option<Band> {
        Some(Band { half_bandwidth: 11, border: 3 })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A flat last element from x = 0 to 1 (m), 5 mm thick, a 5 mm ball at `c`; node b turned
    /// by `twist` about the axis.
    fn approach(c: Vector3<f64>, twist: f64, u: &SVector<f64, LOCAL>) -> f64 {
        let a = (Vector3::zeros(), Matrix3::identity());
        let r = UnitQuaternion::from_scaled_axis(Vector3::new(twist, 0.0, 0.0));
        let b = (Vector3::new(1.0, 0.0, 0.0), r.to_rotation_matrix().into_inner());
        approach_of(u, &c, &a, &b, (0.005, 0.0025, Face::Thickness), (false, true))
    }

    /// The paper's strip, 1 m long along x, thickness along z, in `elements` equal elements,
    /// free.
    fn strip(elements: usize) -> BeamModel {
        let steel = simo_beam::Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = simo_beam::Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let (start, end) = (Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0));
        let mesh = simo_beam::Mesh::straight(start, end, elements, section, Vector3::z()).unwrap();
        BeamModel::new(mesh).unwrap()
    }

    /// The rank of the twist of `r` from `frame`, a node alone.
    fn twist_rank(frame: &UnitQuaternion<f64>, r: &UnitQuaternion<f64>) -> f64 {
        pseudo_angle(turned_width_axis(frame, r))
    }

    #[test]
    fn the_twist_rank_orders_angles_as_their_size() {
        // Angles of both signs from 1e-12 rad to pi, the ranks strictly in the order of |angle|
        // (the largest twist's node is chosen by it).
        let mut angles: Vec<f64> = (0..=400).map(|k| 1e-12 * (k as f64 * 0.07).exp()).collect();
        angles.retain(|a| *a <= std::f64::consts::PI);
        angles.extend([1.0, 1.5, std::f64::consts::FRAC_PI_2, 1.6, 3.0, std::f64::consts::PI]);
        angles.sort_by(f64::total_cmp);
        angles.dedup();
        let rank = |a: f64| pseudo_angle((a.cos(), a.sin()));
        for pair in angles.windows(2) {
            for sign in [1.0, -1.0] {
                assert!(rank(sign * pair[0]) < rank(sign * pair[1]), "{pair:?}");
            }
            assert_eq!(rank(pair[0]).to_bits(), rank(-pair[0]).to_bits());
        }
        assert_eq!(pseudo_angle((0.0, 0.0)).to_bits(), 0.0_f64.to_bits());
        // The block kernel picks the node the ranks pick, ties to the last: 150 nodes (three
        // blocks) twisted by angles of both signs, the largest twice.
        let frames: Vec<_> = (0..150)
            .map(|n| UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.01 * n as f64, 0.3)))
            .collect();
        for largest in [0, 63, 64, 100, 149] {
            let twist = |n: usize| match n {
                _ if n == largest || n == largest / 2 => 0.9,
                _ => 0.5 * ((n as f64) * 0.37).sin(),
            };
            let rotations: Vec<_> = frames
                .iter()
                .enumerate()
                .map(|(n, f)| {
                    f * UnitQuaternion::from_scaled_axis(Vector3::new(twist(n), 0.0, 0.0))
                })
                .collect();
            let scalar = (0..150).fold(None, |best: Option<(usize, f64)>, n| {
                let rank = twist_rank(&frames[n], &rotations[n]);
                if best.is_none_or(|b| rank >= b.1) {
                    Some((n, rank))
                } else {
                    best
                }
            });
            assert_eq!(most_twisted_node(&frames, &rotations, -1.0), scalar.map(|b| b.0));
            let node = Some(largest.max(largest / 2));
            assert_eq!(most_twisted_node(&frames, &rotations, -1.0), node);
            // None at or above the largest rank's floor, the node just below it.
            let rank = scalar.map_or(0.0, |b| b.1);
            assert_eq!(most_twisted_node(&frames, &rotations, rank), None);
            assert_eq!(most_twisted_node(&frames, &rotations, rank * (1.0 - 1e-12)), node);
        }
        assert_eq!(most_twisted_node(&[], &[], -1.0), None);
        // The rank of a turn is its pseudo-angle.
        let frame = UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, 0.3));
        let turned = frame * UnitQuaternion::from_scaled_axis(Vector3::new(-0.4, 0.0, 0.0));
        assert!(
            (twist_rank(&frame, &turned) - pseudo_angle((0.4_f64.cos(), 0.4_f64.sin()))).abs()
                < 1e-15
        );
    }

    #[test]
    fn an_accepted_state_s_strains_are_its_last_force_pass_s_or_their_own() {
        // The strains handed on from the last net force's pass are that configuration's;
        // without it they are computed: both the same as a pass of the strains alone, to the
        // bit, on a bent and twisted strip. Each net force is counted.
        use crate::solve::struck::Struck;
        let beam = strip(6).support(0, simo_beam::Support::Clamped).unwrap();
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam3d::new(beam, (0.01, 0.0, 0.005), 0.0, 0.0025, &law);
        let state = |k: f64| {
            let mut beam = model.beam().reference_state();
            for (i, (x, r)) in beam.positions.iter_mut().zip(&mut beam.rotations).enumerate() {
                let s = i as f64 / 6.0;
                x.z += 1e-3 * k * s * s;
                *r = UnitQuaternion::from_scaled_axis(Vector3::new(
                    2e-3 * k * s,
                    -2e-3 * k * s,
                    0.0,
                ));
            }
            BallOnBeam3dConfig { beam, ball: Vector3::new(1.0, 0.0, 0.01) }
        };
        let alone = |q: &BallOnBeam3dConfig| {
            let mut out = vec![(0.0, 0.0, 0.0); 6];
            let mut plane = vec![(0.0, 0.0, 0.0); 6];
            model.beam().each_strain(&q.beam, |e, s| {
                out[e] = (s.gamma[0], s.gamma[2], -s.kappa[1]);
                plane[e] = (s.kappa[2], s.kappa[0], s.gamma[1]);
            });
            (out, plane)
        };
        let (a, b) = (state(1.0), state(2.0));
        let n = hht::Model::ndof(&model);
        let mut force = faer::Col::<f64>::zeros(n);
        let mut kept = (vec![(0.0, 0.0, 0.0); 6], vec![(0.0, 0.0, 0.0); 6]);
        assert!(!model.last_pass_strains(&mut kept.0, &mut kept.1));
        hht::Model::net_force(&model, 0.0, &a, faer::Col::zeros(n).as_ref(), force.as_mut());
        assert_eq!(Struck::force_passes(&model), 1);
        assert!(model.last_pass_strains(&mut kept.0, &mut kept.1));
        for (q, last_pass) in [(&a, true), (&b, false), (&a, false)] {
            let (mut out, mut plane) = (vec![(9.0, 9.0, 9.0); 6], vec![(9.0, 9.0, 9.0); 6]);
            model.section_strains(q, &mut out, &mut plane, last_pass);
            assert_eq!((out, plane), alone(q));
        }
    }

    #[test]
    fn the_strain_energy_from_the_struck_strains_is_the_elements_own() {
        // A strip bent, sheared, stretched and twisted, struck on either face from either
        // side: the strain energy from the struck face's strains and their weights is the sum
        // of `Element::energy` (the weights follow the strains only while `struck_strains` is
        // a signed permutation of them).
        use crate::solve::struck::Struck;
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let beam = strip(6);
        let mut q =
            BallOnBeam3dConfig { beam: beam.reference_state(), ball: Vector3::new(0.5, 0.0, 1.0) };
        for (node, (x, r)) in q.beam.positions.iter_mut().zip(&mut q.beam.rotations).enumerate() {
            let k = node as f64;
            *x += Vector3::new(1e-5 * k, 2e-5 * k * k, -3e-5 * k);
            *r *= UnitQuaternion::from_scaled_axis(Vector3::new(2e-3 * k, -1e-3 * k, 4e-4 * k * k));
        }
        let exact: f64 = beam
            .mesh()
            .elements
            .iter()
            .map(|e| {
                let [a, b] = e.nodes;
                let x = [&q.beam.positions[a], &q.beam.positions[b]];
                e.energy(x, [&q.beam.rotations[a], &q.beam.rotations[b]])
            })
            .sum();
        let zero = faer::Col::<f64>::zeros(hht::Model::ndof(&beam) + 3);
        for (face, up) in [
            (Face::Thickness, Vector3::z()),
            (Face::Thickness, -Vector3::z()),
            (Face::Width, Vector3::y()),
            (Face::Width, -Vector3::y()),
        ] {
            let model =
                BallOnBeam3d::striking(strip(6), (0.01, 0.0, 0.005), (0.0, up, face), 0.0025, &law);
            let (mut strains, mut plane) = (vec![(0.0, 0.0, 0.0); 6], vec![(0.0, 0.0, 0.0); 6]);
            model.section_strains(&q, &mut strains, &mut plane, false);
            let energy = model.beam_energy(&q, zero.as_ref(), &strains, &plane);
            assert!((energy - exact).abs() <= 1e-12 * exact, "{face:?} {up}: {energy} vs {exact}");
        }
    }

    #[test]
    fn the_predictor_s_inertial_force_is_the_whole_one_to_the_bit() {
        // The coupled model's predictor's inertial force (the beam's rotations' rows anew,
        // the rest and the ball's rows from the old force at the same acceleration) against
        // the whole force at the new velocity: the same bits, the ball's rows included.
        let beam = || strip(6).support(0, simo_beam::Support::Clamped).unwrap();
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam3d::new(beam(), (0.01, 9.81, 0.005), 0.005, 0.0025, &law);
        let n = hht::Model::ndof(&model);
        let q = BallOnBeam3dConfig { beam: beam().reference_state(), ball: Vector3::zeros() };
        let wave = |scale: f64, phase: f64| {
            faer::Col::<f64>::from_fn(n, |i| scale * (1.7 * i as f64 + phase).sin())
        };
        let (v_old, v_new, a) = (wave(3.0, 0.1), wave(5.0, 0.7), wave(2e4, 0.3));
        let force = |v: &faer::Col<f64>| {
            let mut out = faer::Col::<f64>::zeros(n);
            hht::Model::inertial_force(&model, &q, v.as_ref(), a.as_ref(), out.as_mut());
            out
        };
        let (old, whole) = (force(&v_old), force(&v_new));
        let mut predicted = faer::Col::<f64>::from_fn(n, |_| f64::NAN);
        let (v, a) = (v_new.as_ref(), a.as_ref());
        hht::Model::predicted_inertial_force(&model, &q, v, a, old.as_ref(), predicted.as_mut());
        let bits = |x: &faer::Col<f64>| x.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&predicted), bits(&whole));
        assert_ne!(bits(&old), bits(&whole));
    }

    #[test]
    fn a_kept_contact_point_is_the_one_of_the_same_numbers() {
        // The ball pressed 1 um into the last of 4 elements of a 1 m strip, 5 mm off the
        // centreline: the point kept from a value-only call is not served for a gradient, and
        // a moved ball, node or twist gets its own point, the same as a fresh model's.
        let beam = || strip(4);
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam3d::new(beam(), (0.01, 0.0, 0.005), 0.005, 0.0025, &law);
        let mut q = BallOnBeam3dConfig {
            beam: beam().reference_state(),
            ball: Vector3::new(0.9, 0.005, 0.0075 - 1e-6),
        };
        let value = model.contact_point(&q, Order::Value);
        let gradient = model.contact_point(&q, Order::Gradient);
        assert!((value.delta - 1e-6).abs() < 1e-15 && (gradient.delta - value.delta).abs() == 0.0);
        // d delta / d (ball z) = -1 on the upper face.
        assert!((gradient.gradient[2] + 1.0).abs() < 1e-12, "{:?}", gradient.gradient);
        for moved in 0..3 {
            match moved {
                0 => q.ball.z -= 1e-7,
                1 => q.beam.positions[4].z += 1e-7,
                _ => {
                    q.beam.rotations[4] *=
                        UnitQuaternion::from_scaled_axis(Vector3::new(1e-5, 0.0, 0.0))
                }
            }
            let fresh = BallOnBeam3d::new(beam(), (0.01, 0.0, 0.005), 0.005, 0.0025, &law);
            let (kept, new) = (
                model.contact_point(&q, Order::Gradient),
                fresh.contact_point(&q, Order::Gradient),
            );
            assert!((kept.delta - new.delta).abs() == 0.0 && kept.gradient == new.gradient);
            assert!((kept.delta - value.delta).abs() > 2e-8, "{moved}: {}", kept.delta);
        }
        // The value alone and the value with the gradient are the same bits (`touching` asks
        // for the gradient at once in contact and decides by its value): on the moved and
        // twisted strip, and past its end (the ball over the end's edge).
        for ball_x in [0.9, 1.0 + 2e-3] {
            q.ball.x = ball_x;
            let fresh = || BallOnBeam3d::new(beam(), (0.01, 0.0, 0.005), 0.005, 0.0025, &law);
            let value = fresh().contact_point(&q, Order::Value).delta;
            let with_gradient = fresh().contact_point(&q, Order::Gradient).delta;
            assert_eq!(
                value.to_bits(),
                with_gradient.to_bits(),
                "{ball_x}: {value} {with_gradient}"
            );
        }
    }

    #[test]
    fn a_twist_moves_the_face_under_an_offset_ball_by_offset_times_twist() {
        // The ball 10 mm off the centreline above the twisted end (theta = 1e-3): the face under
        // it is lower by e sin(theta) (tilted plane: (c - x).n = -e sin + z cos).
        let zero = SVector::<f64, LOCAL>::zeros();
        let c = Vector3::new(1.0, 0.01, 0.0075);
        let flat = approach(c, 0.0, &zero);
        let twisted = approach(c, 1e-3, &zero);
        let expected = 0.0075 - (-0.01 * 1e-3f64.sin() + 0.0075 * 1e-3f64.cos());
        assert!(flat.abs() < 1e-15, "{flat:e}");
        assert!((twisted - flat - expected).abs() < 1e-15, "{twisted:e} vs {expected:e}");
    }

    /// The approach's gradient in dual numbers, one unknown a pass: the reference the
    /// written-out [`approach_gradient`] is checked against.
    fn dual_gradient(
        c: &Vector3<f64>,
        a: &Node,
        b: &Node,
        surface: (f64, f64, Face),
        ends: (bool, bool),
    ) -> (f64, SVector<f64, LOCAL>) {
        let mut gradient = SVector::<f64, LOCAL>::zeros();
        let mut delta = 0.0;
        for (j, g) in gradient.iter_mut().enumerate() {
            let u = SVector::<num_dual::Dual64, LOCAL>::from_fn(|k, _| {
                num_dual::Dual64::new(0.0, if k == j { 1.0 } else { 0.0 })
            });
            let d = approach_of(&u, c, a, b, surface, ends);
            (delta, *g) = (d.re, d.eps);
        }
        (delta, gradient)
    }

    #[test]
    fn the_written_out_gradient_is_the_dual_numbers_one() {
        // On the face and past either end, on both kinds of face, the ball above and below,
        // at a bent and twisted element: the same approach and gradient as the dual numbers
        // give, to round-off.
        let turned = |v: [f64; 3]| {
            UnitQuaternion::from_scaled_axis(Vector3::from(v)).to_rotation_matrix().into_inner()
        };
        let a = (Vector3::new(0.0, 1e-4, 2e-4), turned([3e-3, -1e-3, 5e-4]));
        let b = (Vector3::new(1.0, -1e-4, -3e-4), turned([-2e-3, 4e-3, 1e-3]));
        let cases = [
            (Vector3::new(0.6, 0.008, 0.0074), (false, false)),
            (Vector3::new(0.3, -0.006, -0.0073), (true, true)),
            (Vector3::new(1.003, 0.007, 0.0071), (false, true)),
            (Vector3::new(1.002, -0.004, -0.0072), (true, true)),
            (Vector3::new(-0.002, 0.005, 0.0073), (true, false)),
        ];
        for face in [Face::Thickness, Face::Width] {
            for (c, ends) in cases {
                // On a width face the ball sits across the width: swap its y and z.
                let c = if face == Face::Width { Vector3::new(c.x, c.z, c.y) } else { c };
                let surface = (0.005, 0.0025, face);
                let (delta, g) = approach_gradient(&c, &a, &b, surface, ends);
                let (reference, expected) = dual_gradient(&c, &a, &b, surface, ends);
                assert!(
                    (delta - reference).abs() < 1e-16,
                    "{face:?} {c:?}: {delta} vs {reference}"
                );
                for i in 0..LOCAL {
                    assert!(
                        (g[i] - expected[i]).abs() < 1e-12 * (1.0 + expected[i].abs()),
                        "{face:?} {c:?} unknown {i}: {} vs {}",
                        g[i],
                        expected[i]
                    );
                }
            }
        }
    }

    #[test]
    fn the_twist_after_a_corner_is_about_its_own_member_s_axis() {
        // An L of two members in the x-y plane (along x, then along y), its corner node turned
        // 0.01 rad about y, the second member's axis: the second member's first section is
        // twisted 0.01 rad, the first member's last one not at all (its axis is x), and the
        // node's own reading is the first member's.
        use simo_beam::scene::{SectionSpec, SegmentSpec};
        let section = SectionSpec {
            youngs_modulus: Some(2.1e11),
            poisson_ratio: Some(0.3),
            density: Some(7850.0),
            width: Some(0.025),
            thickness: Some(0.005),
            ..SectionSpec::default()
        };
        let segments = [
            SegmentSpec::straight(Some([0.0, 0.0, 0.0]), [0.5, 0.0, 0.0], 4),
            SegmentSpec::straight(None, [0.5, 0.5, 0.0], 4),
        ];
        let (beam, _) = simo_beam::scene::structure(&section, &segments, &[]).unwrap();
        let law = hertz::Hertz::new(1.15e11, 0.005).unwrap();
        let model = BallOnBeam3d::new(beam, (0.01, 0.0, 0.005), 0.0, 0.0025, &law);
        let mut q = BallOnBeam3dConfig {
            beam: model.beam().reference_state(),
            ball: Vector3::new(0.6, 0.25, 0.01),
        };
        let turn = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.01, 0.0));
        q.beam.rotations[4] = turn * q.beam.rotations[4];
        assert!(!model.beam().mesh().elements[4].straight());
        let (first, second) = (model.end_twist(&q, 3, 1), model.end_twist(&q, 4, 0));
        assert!((second.abs() - 0.01).abs() < 1e-12, "{second}");
        assert!(first.abs() < 1e-12, "{first}");
        assert!(model.node_twist(&q, 4).abs() < 1e-12);
        // The largest anywhere is the corner's, read about the second member's axis.
        let (node, largest) = model.largest_twist(&q, -1.0).unwrap();
        assert_eq!(node, 4);
        assert!((largest - 0.01).abs() < 1e-12, "{largest}");
        // Asked beyond a twist: none at the largest itself, the corner's just below it (every
        // node then ranks below the floor), and a node's where it is the largest.
        assert_eq!(model.largest_twist(&q, largest), None);
        assert_eq!(model.largest_twist(&q, largest * (1.0 - 1e-9)), Some((4, largest)));
        let twist = UnitQuaternion::from_scaled_axis(Vector3::new(0.02, 0.0, 0.0));
        q.beam.rotations[2] *= twist;
        let (node, by) = model.largest_twist(&q, largest).unwrap();
        assert!(node == 2 && (by - 0.02).abs() < 1e-12, "{node} {by}");
        assert_eq!(model.largest_twist(&q, by), None);
        // An ulp less than a node's own twist is beaten by it (the floor's margin).
        assert_eq!(model.largest_twist(&q, f64::from_bits(by.to_bits() - 1)), Some((2, by)));
    }

    #[test]
    fn at_a_corner_the_gradient_turns_back_onto_the_nodes_rotations() {
        // The element after a corner: its end frames are its nodes' turned by O (a quarter
        // turn about z at the corner node a, a small one at b), a node's increment theta
        // turning its end frame to R exp(theta^) O. Central differences of that exact motion
        // against the written-out gradient (and the dual numbers through the turns) on both
        // faces: the rotation rows are O times the end frame's.
        let rot = |v: [f64; 3]| {
            UnitQuaternion::from_scaled_axis(Vector3::from(v)).to_rotation_matrix().into_inner()
        };
        let (ra, rb) = (rot([3e-3, -1e-3, 5e-4]), rot([-2e-3, 4e-3, 1e-3]));
        let turns: Turns = (rot([0.0, 0.0, std::f64::consts::FRAC_PI_2]), rot([1e-3, 0.0, 2e-3]));
        let (xa, xb) = (Vector3::new(0.0, 1e-4, 2e-4), Vector3::new(1.0, -1e-4, -3e-4));
        let a = (xa, ra * turns.0);
        let b = (xb, rb * turns.1);
        for face in [Face::Thickness, Face::Width] {
            let c = Vector3::new(0.6, 0.008, 0.0074);
            let c = if face == Face::Width { Vector3::new(c.x, c.z, c.y) } else { c };
            let surface = (0.005, 0.0025, face);
            let exact = |u: &SVector<f64, LOCAL>| {
                let end = |r: &Matrix3<f64>, o: &Matrix3<f64>, k: usize| {
                    r * rot([u[k], u[k + 1], u[k + 2]]) * o
                };
                let mut v = *u;
                for k in [6, 7, 8, 12, 13, 14] {
                    v[k] = 0.0;
                }
                let (ta, tb) = ((xa, end(&ra, &turns.0, 6)), (xb, end(&rb, &turns.1, 12)));
                approach_of(&v, &c, &ta, &tb, surface, (false, false))
            };
            let (delta, g) =
                approach_gradient_turned(&c, (&a, &b, Some(&turns)), surface, (false, false));
            let zero = SVector::<f64, LOCAL>::zeros();
            assert!((delta - exact(&zero)).abs() < 1e-16, "{face:?}");
            let dual = |j: usize| {
                let u = SVector::<num_dual::Dual64, LOCAL>::from_fn(|k, _| {
                    num_dual::Dual64::new(0.0, if k == j { 1.0 } else { 0.0 })
                });
                approach_turned(&u, &c, (&a, &b, Some(&turns)), surface, (false, false)).eps
            };
            let h = 1e-7;
            for j in 0..LOCAL {
                let mut u = zero;
                u[j] = h;
                let plus = exact(&u);
                u[j] = -h;
                let central = (plus - exact(&u)) / (2.0 * h);
                // Central differences at h = 1e-7 on an approach of order 1e-3: truncation
                // ~h^2 and round-off ~1e-16 / h, both below 1e-8.
                assert!((g[j] - central).abs() < 1e-8, "{face:?} {j}: {} vs {central}", g[j]);
                assert!((g[j] - dual(j)).abs() < 1e-12, "{face:?} {j}: {} vs {}", g[j], dual(j));
            }
        }
    }

    #[test]
    fn the_gradient_and_hessian_are_the_approach_s_derivatives() {
        // Central differences of the approach along each local unknown (the rotation
        // increments through the exact exponential, which agrees with the second-order
        // expansion to second order at theta = 0), at a bent and twisted configuration.
        let c = Vector3::new(0.7, 0.008, 0.0074);
        let a = (
            Vector3::new(0.0, 0.0, 1e-4),
            UnitQuaternion::from_scaled_axis(Vector3::new(2e-3, -1e-3, 5e-4))
                .to_rotation_matrix()
                .into_inner(),
        );
        let b = (
            Vector3::new(1.0, 1e-5, -2e-4),
            UnitQuaternion::from_scaled_axis(Vector3::new(-1e-3, 3e-3, 0.0))
                .to_rotation_matrix()
                .into_inner(),
        );
        let exact = |u: &SVector<f64, LOCAL>| {
            // Rotations by the exact exponential, then the approach with zero increments.
            let turn = |n: &Node, k: usize| {
                let th = Vector3::new(u[k], u[k + 1], u[k + 2]);
                n.1 * UnitQuaternion::from_scaled_axis(th).to_rotation_matrix().into_inner()
            };
            let mut v = *u;
            for k in [6, 7, 8, 12, 13, 14] {
                v[k] = 0.0;
            }
            let (ta, tb) = ((a.0, turn(&a, 6)), (b.0, turn(&b, 12)));
            approach_of(&v, &c, &ta, &tb, (0.005, 0.0025, Face::Thickness), (false, true))
        };
        let zero = SVector::<f64, LOCAL>::zeros();
        let (_, g) = approach_gradient(&c, &a, &b, (0.005, 0.0025, Face::Thickness), (false, true));
        let (_, _, hess) = num_dual::hessian(
            |u: SVector<Dual2SVec64<LOCAL>, LOCAL>| {
                approach_of(&u, &c, &a, &b, (0.005, 0.0025, Face::Thickness), (false, true))
            },
            &zero,
        );
        let h = 1e-5;
        for i in 0..LOCAL {
            let mut up = zero;
            up[i] = h;
            let fd = (exact(&up) - exact(&-up)) / (2.0 * h);
            assert!((fd - g[i]).abs() < 1e-8, "gradient {i}: {fd} vs {}", g[i]);
            for j in 0..LOCAL {
                let mut uj = zero;
                uj[j] = h;
                let fd2 = (exact(&(up + uj)) - exact(&(up - uj)) - exact(&(uj - up))
                    + exact(&(-up - uj)))
                    / (4.0 * h * h);
                // A rotation's second derivative through exp is symmetrised (the Hessian of a
                // map on the group at the identity): compare the symmetric parts.
                let sym = 0.5 * (hess[(i, j)] + hess[(j, i)]);
                assert!(
                    (fd2 - sym).abs() < 1e-4 * (1.0 + sym.abs()),
                    "hessian {i},{j}: {fd2} vs {sym}"
                );
            }
        }
    }
}
