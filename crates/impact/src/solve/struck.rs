//! What the fe run needs of a ball-on-beam model, the planar one ([`BallOnBeam`]) or the 3D one
//! ([`BallOnBeam3d`]): the contact, the ball, the struck face at the impact point, the section
//! strains and the energy, and a planar view for the recorders. The run (`solve/fe.rs`) is
//! written once against it.

use super::ball_on_beam::{BallOnBeam, BallOnBeamConfig, Order};
use super::ball_on_beam3d::{BallOnBeam3d, BallOnBeam3dConfig};
use faer::ColRef;
use hertz::{ContactForce, ContactLaw};
use hht::Model;
use simo_beam::{PlanarBeam, PlanarState};

/// A ball on a beam, as the fe run steps it.
pub(crate) trait Struck<L: ContactLaw>: Model {
    /// The contact law and its history.
    fn law(&self) -> &L;
    fn law_state(&self) -> &L::State;
    /// Commits the law's history at an accepted state's approach and rate.
    fn commit_law(&mut self, delta: f64, rate: f64);
    /// Approach (m), positive in compression.
    fn approach(&self, q: &Self::Config) -> f64;
    /// Approach, its rate and the law's force.
    fn contact(&self, q: &Self::Config, v: ColRef<'_, f64>) -> (f64, f64, ContactForce);
    /// Keeps the contact element of an accepted state.
    fn commit_contact_element(&mut self, q: &Self::Config);
    /// The contact element and the ball's projection on it.
    fn contact_element(&self, q: &Self::Config) -> (usize, f64);
    /// How many of the last unknowns are the ball's.
    fn ball_unknowns(&self) -> usize;
    /// The ball centre's coordinate along the direction it comes from (m; its travel is the
    /// drop of this), and its speed toward the face (m/s).
    fn ball_height(&self, q: &Self::Config) -> f64;
    fn ball_speed(&self, v: ColRef<'_, f64>) -> f64;
    /// Sets the ball's velocity in `v` to `speed` (m/s) toward the face.
    fn launch(&self, speed: f64, v: &mut faer::Col<f64>);
    /// The struck face's displacement at the impact point (element, local coordinate) from its
    /// place at rest (m), along the same direction (not its coordinate: a structure need not
    /// sit at zero along the strike), and the unknowns and weights whose sum gives its rate and
    /// acceleration.
    fn face_height(&self, q: &Self::Config, impact: (usize, f64)) -> f64;
    fn face_rows(&self, impact: (usize, f64)) -> Vec<(usize, f64)>;
    /// The struck section's rotation about the beam's axis (rad; 0 in the plane).
    fn twist(&self, q: &Self::Config, impact: (usize, f64)) -> f64;
    /// The node whose section is turned most about its own axis, and by how much (rad), if
    /// by more than `beyond` (rad; the largest so far, a negative number for any); `None`
    /// otherwise and in the plane.
    fn largest_twist(&self, q: &Self::Config, beyond: f64) -> Option<(usize, f64)>;
    /// How many net forces the model has evaluated. A state returned by an integrator step is
    /// the configuration of the step's last net force (`hht`'s Newton iteration evaluates the
    /// balance at its last iterate and returns that iterate), so while this count has not
    /// moved since the step, that pass's strains are the state's.
    fn force_passes(&self) -> u64;
    /// Each element's (extension, shear, curvature) in the beam's plane (x-z), the planar
    /// beam's sign convention, and out of it (the 3D beam's: the bending curvature about the
    /// thickness axis, the twist rate (1/m) and the shear across the width; left as they are
    /// in the plane). With `last_pass`, `q` is the configuration of the last net force (the
    /// caller knows it by [`Struck::force_passes`]) and the strains are taken from that pass
    /// (the same bits) instead of a pass of their own.
    fn section_strains(
        &self,
        q: &Self::Config,
        out: &mut [(f64, f64, f64)],
        out_of_plane: &mut [OutOfPlane],
        last_pass: bool,
    );
    /// The beam's strain (and springs') plus kinetic energy (J), given the section strains
    /// of `q`.
    fn beam_energy(
        &self,
        q: &Self::Config,
        v: ColRef<'_, f64>,
        strains: &[(f64, f64, f64)],
        out_of_plane: &[OutOfPlane],
    ) -> f64;
    /// The beam in the x-z plane, for the recorders (the 3D model's projection is written
    /// into `scratch`).
    fn planar_view<'s>(
        &'s self,
        q: &'s Self::Config,
        scratch: &'s mut PlanarState,
    ) -> &'s PlanarState;
    /// The struck face's static flexibility at the impact point (m/N): a static solve of the
    /// beam alone (its springs included) under a unit force there.
    fn static_flexibility(&self, impact: (usize, f64)) -> Option<f64>;
}

/// An element's strains out of the beam's plane (x-z): the bending curvature about the
/// thickness axis, the twist rate (1/m) and the shear strain across the width.
pub(crate) type OutOfPlane = (f64, f64, f64);

/// The static flexibility (m/N) of `model` at the rows `rows` (unknown, weight): `K u = f` at
/// the configuration `q` for the force `f = rows` (a unit force shared between the unknowns
/// as the rows weigh them), read back as `rows . u`, by the sparse LU the integrator uses (one
/// static solve a run). `None` if the model is not held (a singular `K`) or the flexibility
/// is not positive.
fn static_flexibility_of<M: Model>(model: &M, q: &M::Config, rows: &[(usize, f64)]) -> Option<f64> {
    static_solve(model, q, rows).map(|(flexibility, _)| flexibility)
}

/// The static flexibility (m/N) of a 3D beam at rest at the face rows `rows` and its
/// displacement under a unit force along the strike (`-rows`: the force pushes the face along
/// the ball's velocity); `None` where it is not held.
pub(crate) fn static_response(
    beam: &simo_beam::BeamModel,
    rows: &[(usize, f64)],
) -> Option<(f64, faer::Col<f64>)> {
    static_solve(beam, &beam.reference_state(), rows).map(|(f, u)| (f, -u))
}

/// [`static_response`] of a beam linearised at rest (its stiffness already assembled).
pub(crate) fn static_response_at_rest(
    beam: &simo_beam::AtRest,
    rows: &[(usize, f64)],
) -> Option<(f64, faer::Col<f64>)> {
    solve_stiffness(beam.ndof(), beam.stiffness(), rows).map(|(f, u)| (f, -u))
}

/// [`static_flexibility_of`] and the displacement `K^-1 rows` it reads.
fn static_solve<M: Model>(
    model: &M,
    q: &M::Config,
    rows: &[(usize, f64)],
) -> Option<(f64, faer::Col<f64>)> {
    let n = model.ndof();
    let zero = faer::Col::<f64>::zeros(n);
    let mut k = hht::Triplets::new();
    let w = hht::NewtonWeights::stiffness();
    model.tangent(0.0, q, zero.as_ref(), zero.as_ref(), w, &mut k);
    solve_stiffness(n, &k, rows)
}

/// `rows . K^-1 rows` and `K^-1 rows` for the stiffness `k` over `n` unknowns.
fn solve_stiffness(
    n: usize,
    k: &hht::Triplets,
    rows: &[(usize, f64)],
) -> Option<(f64, faer::Col<f64>)> {
    let mut lu = hht::SparseLu::new();
    lu.factor(n, k, 0.0).ok()?;
    let mut f = faer::Col::<f64>::zeros(n);
    for (i, w) in rows {
        f[*i] += w;
    }
    let u = lu.solve(&f, 0.0).ok()?;
    let flexibility: f64 = rows.iter().map(|(i, w)| w * u[*i]).sum();
    (flexibility.is_finite() && flexibility > 0.0).then_some((flexibility, u))
}

/// Linear interpolation at `xi` between two nodes' values.
fn between(values: (f64, f64), xi: f64) -> f64 {
    (1.0 - xi) * values.0 + xi * values.1
}

impl<L: ContactLaw> Struck<L> for BallOnBeam<'_, L> {
    fn law(&self) -> &L {
        self.law
    }
    fn law_state(&self) -> &L::State {
        &self.law_state
    }
    fn commit_law(&mut self, delta: f64, rate: f64) {
        self.law.commit(&mut self.law_state, delta, rate);
    }
    fn approach(&self, q: &BallOnBeamConfig) -> f64 {
        BallOnBeam::approach(self, q)
    }
    fn contact(&self, q: &BallOnBeamConfig, v: ColRef<'_, f64>) -> (f64, f64, ContactForce) {
        BallOnBeam::contact(self, q, v)
    }
    fn commit_contact_element(&mut self, q: &BallOnBeamConfig) {
        BallOnBeam::commit_contact_element(self, q);
    }
    fn contact_element(&self, q: &BallOnBeamConfig) -> (usize, f64) {
        let p = self.contact_point(q, Order::Value);
        (p.element, p.xi)
    }
    fn ball_unknowns(&self) -> usize {
        2
    }
    fn ball_height(&self, q: &BallOnBeamConfig) -> f64 {
        q.ball.y
    }
    fn ball_speed(&self, v: ColRef<'_, f64>) -> f64 {
        -v[v.nrows() - 1]
    }
    fn launch(&self, speed: f64, v: &mut faer::Col<f64>) {
        let n = v.nrows();
        v[n - 1] = -speed;
    }
    fn face_height(&self, q: &BallOnBeamConfig, (i, xi): (usize, f64)) -> f64 {
        between((q.beam.z[i], q.beam.z[i + 1]), xi)
    }
    fn face_rows(&self, (i, xi): (usize, f64)) -> Vec<(usize, f64)> {
        [(i, 1.0 - xi), (i + 1, xi)]
            .into_iter()
            .filter_map(|(node, w)| self.beam().dof(node, 1).map(|d| (d, w)))
            .collect()
    }
    fn twist(&self, _q: &BallOnBeamConfig, _impact: (usize, f64)) -> f64 {
        0.0
    }
    fn largest_twist(&self, _q: &BallOnBeamConfig, _beyond: f64) -> Option<(usize, f64)> {
        None
    }
    fn force_passes(&self) -> u64 {
        BallOnBeam::force_passes(self)
    }
    fn section_strains(
        &self,
        q: &BallOnBeamConfig,
        out: &mut [(f64, f64, f64)],
        _out_of_plane: &mut [OutOfPlane],
        last_pass: bool,
    ) {
        if !(last_pass && self.last_pass_strains(out)) {
            self.beam().all_section_strains(&q.beam, out);
        }
    }
    fn beam_energy(
        &self,
        q: &BallOnBeamConfig,
        v: ColRef<'_, f64>,
        strains: &[(f64, f64, f64)],
        _out_of_plane: &[OutOfPlane],
    ) -> f64 {
        let beam = self.beam();
        beam.strain_energy_of(strains)
            + beam.spring_energy(&q.beam)
            + beam.kinetic_energy(v.subrows(0, beam.ndof()))
    }
    fn planar_view<'s>(
        &'s self,
        q: &'s BallOnBeamConfig,
        _scratch: &'s mut PlanarState,
    ) -> &'s PlanarState {
        &q.beam
    }
    fn static_flexibility(&self, impact: (usize, f64)) -> Option<f64> {
        let beam: &PlanarBeam = self.beam();
        static_flexibility_of(beam, &beam.reference_state(), &self.face_rows(impact))
    }
}

impl<L: ContactLaw> Struck<L> for BallOnBeam3d<'_, L> {
    fn law(&self) -> &L {
        self.law
    }
    fn law_state(&self) -> &L::State {
        &self.law_state
    }
    fn commit_law(&mut self, delta: f64, rate: f64) {
        self.law.commit(&mut self.law_state, delta, rate);
    }
    fn approach(&self, q: &BallOnBeam3dConfig) -> f64 {
        BallOnBeam3d::approach(self, q)
    }
    fn contact(&self, q: &BallOnBeam3dConfig, v: ColRef<'_, f64>) -> (f64, f64, ContactForce) {
        BallOnBeam3d::contact(self, q, v)
    }
    fn commit_contact_element(&mut self, q: &BallOnBeam3dConfig) {
        BallOnBeam3d::commit_contact_element(self, q);
    }
    fn contact_element(&self, q: &BallOnBeam3dConfig) -> (usize, f64) {
        let p = self.contact_point(q, Order::Value);
        (p.element, p.xi)
    }
    fn ball_unknowns(&self) -> usize {
        3
    }
    fn ball_height(&self, q: &BallOnBeam3dConfig) -> f64 {
        self.up().dot(&q.ball)
    }
    fn ball_speed(&self, v: ColRef<'_, f64>) -> f64 {
        let n = v.nrows();
        -(0..3).map(|k| self.up()[k] * v[n - 3 + k]).sum::<f64>()
    }
    fn launch(&self, speed: f64, v: &mut faer::Col<f64>) {
        let n = v.nrows();
        for k in 0..3 {
            v[n - 3 + k] = -speed * self.up()[k];
        }
    }
    /// The face's point under the ball's offset: the centre line's displacement plus offset x
    /// twist along the face's normal (small rotation, as the modal method reads it).
    fn face_height(&self, q: &BallOnBeam3dConfig, (i, xi): (usize, f64)) -> f64 {
        let rest = &self.beam().mesh().positions;
        let at = |node: usize| self.up().dot(&(q.beam.positions[node] - rest[node]));
        between((at(i), at(i + 1)), xi) + self.offset() * self.facing(i) * self.twist(q, (i, xi))
    }
    /// The translation rows of the two nodes along `up`, and their rotation about the section
    /// axis times the offset (the angular velocities are material, about E1).
    fn face_rows(&self, site: (usize, f64)) -> Vec<(usize, f64)> {
        super::ball_on_beam3d::face_rows(self.beam(), (self.up(), self.face(), self.offset()), site)
    }
    /// The element's two end sections' rotation about its axis from their reference frames,
    /// interpolated: the angle that turns E2 toward E3.
    fn twist(&self, q: &BallOnBeam3dConfig, (i, xi): (usize, f64)) -> f64 {
        between((self.end_twist(q, i, 0), self.end_twist(q, i, 1)), xi)
    }
    fn largest_twist(&self, q: &BallOnBeam3dConfig, beyond: f64) -> Option<(usize, f64)> {
        BallOnBeam3d::largest_twist(self, q, beyond)
    }
    /// The struck face's strains ([`super::ball_on_beam3d::struck_strains`]): on a `[beam]`'s thickness
    /// face (Gamma1, Gamma3, -K2), extension, the shear along the thickness and the bending
    /// curvature about the width axis, signed as the planar beam's (its rotation turns x
    /// toward z, a rotation about +y turns z toward x); out of the plane (K3, K1, Gamma2).
    fn force_passes(&self) -> u64 {
        BallOnBeam3d::force_passes(self)
    }
    fn section_strains(
        &self,
        q: &BallOnBeam3dConfig,
        out: &mut [(f64, f64, f64)],
        out_of_plane: &mut [OutOfPlane],
        last_pass: bool,
    ) {
        let (face, sides) = (self.face(), self.sides());
        if !(last_pass && self.last_pass_strains(out, out_of_plane)) {
            self.beam().each_strain(&q.beam, |e, s| {
                let (g, k) = (s.gamma, s.kappa);
                (out[e], out_of_plane[e]) = super::ball_on_beam3d::struck_strains(
                    face,
                    sides[e],
                    [g[0], g[1], g[2], k[0], k[1], k[2]],
                );
            });
        }
    }
    /// The elements' strain energy from the strains `section_strains` gave (not a second pass
    /// over the elements' rotations), plus the springs' and the kinetic energy.
    fn beam_energy(
        &self,
        q: &BallOnBeam3dConfig,
        v: ColRef<'_, f64>,
        strains: &[(f64, f64, f64)],
        out_of_plane: &[OutOfPlane],
    ) -> f64 {
        let beam = self.beam();
        // `l0 / 2 (Gamma . C_N Gamma + K . C_M K)` an element (`Element::energy_of`), by its
        // weights in the struck face's order (element by element through the elements and back
        // to the six strains, the accepted rows' energy took 2 % of the paper's tip in 3D),
        // element k into partial sum k mod 4 (one chain of additions, its latency set the time).
        let mut parts = [0.0; 4];
        let elements = strains.iter().zip(out_of_plane).zip(self.energy_weights());
        for (k, ((&(a, b, c), &(d, e, f)), w)) in elements.enumerate() {
            parts[k % 4] += w[0] * a * a
                + w[1] * b * b
                + w[2] * c * c
                + w[3] * d * d
                + w[4] * e * e
                + w[5] * f * f;
        }
        let strain = (parts[0] + parts[1]) + (parts[2] + parts[3]);
        strain + beam.spring_energy(&q.beam) + beam.kinetic_energy(v.subrows(0, beam.ndof()))
    }
    /// Along the arc length: the displacement along `up` (the strike's line) and the bending
    /// slope in the strike's plane, as minus the turn of the section's axis E1 toward `up`,
    /// -up . (R0 (psi x E1)) to first order in the section's rotation psi from its reference
    /// frame R0 (signed as the planar beam's theta: on a straight `[beam]` its z and theta,
    /// -psi_2; on a width face the rotation about the thickness axis).
    fn planar_view<'s>(
        &'s self,
        q: &'s BallOnBeam3dConfig,
        scratch: &'s mut PlanarState,
    ) -> &'s PlanarState {
        let n = q.beam.positions.len();
        for v in [&mut scratch.x, &mut scratch.z, &mut scratch.theta] {
            v.resize(n, 0.0);
        }
        let mesh = self.beam().mesh();
        for k in 0..n {
            let moved = q.beam.positions[k] - mesh.positions[k];
            let turned = (mesh.frames[k].inverse() * q.beam.rotations[k]).scaled_axis();
            let axis_turn = mesh.frames[k] * turned.cross(&nalgebra::Vector3::x());
            (scratch.x[k], scratch.z[k], scratch.theta[k]) =
                (mesh.arc_length[k], self.up().dot(&moved), self.up().dot(&axis_turn));
        }
        scratch
    }
    fn static_flexibility(&self, impact: (usize, f64)) -> Option<f64> {
        let beam = self.beam();
        static_flexibility_of(beam, &beam.reference_state(), &self.face_rows(impact))
    }
}
