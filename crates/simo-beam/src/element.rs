//! The two-node element with one-point integration and objective rotation interpolation.
//!
//! Crisfield & Jelenic (1999): interpolate local rotations relative to the reference
//! `Lambda_r = Lambda_1 exp(phi^/2)`, `phi = log(Lambda_1^T Lambda_2)`. At the single Gauss point
//! (the element middle) the local rotation is zero, so with `d = x_2 - x_1`:
//!
//! - midpoint rotation `Lambda_m = Lambda_1 exp(phi^/2)` (the SLERP midpoint),
//! - force strain `Gamma = Lambda_m^T d / l0 - gamma0`, curvature `K = (phi - phi0) / l0`,
//!
//! with `gamma0`, `phi0` the same quantities in the reference configuration (stress-free, so
//! a curved mesh of straight chords is unstressed). Both strains are unchanged by a superposed
//! rigid rotation (objective) and depend only on the current nodal rotations (path
//! independent). Energy `l0 (Gamma . C_N Gamma + K . C_M K) / 2`.
//!
//! Internal force for material rotation variations `delta Lambda_i = Lambda_i Theta_i^`, with
//! `N = C_N Gamma`, `M = C_M K`, `gamma = Lambda_m^T d / l0`, `c = l0 N x gamma`,
//! `m = M + J_r(phi/2)^T c / 2` (derived from the variations
//! `delta phi = J_r(phi)^-1 (Theta_2 - R^T Theta_1)`, `R = exp(phi^)`, and
//! `Theta_m = exp(-phi^/2) Theta_1 + J_r(phi/2) delta phi / 2`):
//!
//! `f_x1 = -Lambda_m N`, `f_x2 = Lambda_m N`, `f_th2 = J_r(phi)^-T m`,
//! `f_th1 = exp(phi^/2) c - R f_th2`.
//!
//! The tangent is the exact derivative of this force along the multiplicative update (forward
//! mode automatic differentiation, one of the 12 directions a pass), so it carries the material
//! and geometric parts and the non-symmetric part away from equilibrium.

use crate::rotation::{
    log_and_half, matrix, right_jacobian_inverse_transpose_times, right_jacobian_transpose_times,
    turn,
};
use crate::section::Section;
use nalgebra::{Quaternion, RealField, SMatrix, SVector, UnitQuaternion, Vector3};
use num_dual::Dual64;

/// Reference data of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    /// Node indices (start, end).
    pub nodes: [usize; 2],
    /// Reference length l0 (m).
    pub length: f64,
    /// Section properties.
    pub section: Section,
    /// Reference `Lambda_m^T d / l0` (dimensionless).
    pub gamma0: Vector3<f64>,
    /// Reference relative rotation vector `log(Lambda_1^T Lambda_2)` (rad).
    pub phi0: Vector3<f64>,
    /// Constant rotation from each node's frame to the element's end frame: identity along a
    /// smooth beam, the corner angle where two legs of a frame meet at a rigid joint.
    pub offsets: [UnitQuaternion<f64>; 2],
}

/// Element strains at the Gauss point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strains<T> {
    /// Force strain Gamma (axial, shear 2, shear 3), dimensionless.
    pub gamma: Vector3<T>,
    /// Curvature K (torsion, bending 2, bending 3) (1/m).
    pub kappa: Vector3<T>,
}

fn cst<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

fn quaternion_to<T: RealField + Copy>(q: &UnitQuaternion<f64>) -> Quaternion<T> {
    Quaternion::new(cst(q.w), cst(q.i), cst(q.j), cst(q.k))
}

/// The configuration `(x, r)` seeded with its variation `j` of `[dx1, th1, dx2, th2]` (0..12),
/// in dual numbers of that one direction: the positions plus `dx_i`, the rotations times
/// `exp(th_i^)` to first order, `q (1, th/2)` (unit only to first order, which is all a first
/// derivative sees). One direction a pass: twelve passes of numbers of two parts ran 1.7x
/// faster than one of numbers carrying twelve derivatives, whose every operation also checks
/// whether they are there.
#[allow(clippy::type_complexity)]
fn seeded_along(
    x: [&Vector3<f64>; 2],
    r: [&UnitQuaternion<f64>; 2],
    j: usize,
) -> (Vector3<Dual64>, Vector3<Dual64>, Quaternion<Dual64>, Quaternion<Dual64>) {
    let p = |k: usize| Dual64::new(0.0, if k == j { 1.0 } else { 0.0 });
    let half = Dual64::from(0.5);
    let turn = |r: &UnitQuaternion<f64>, k: usize| {
        quaternion_to::<Dual64>(r)
            * Quaternion::new(Dual64::from(1.0), p(k) * half, p(k + 1) * half, p(k + 2) * half)
    };
    (
        x[0].map(Dual64::from) + Vector3::new(p(0), p(1), p(2)),
        x[1].map(Dual64::from) + Vector3::new(p(6), p(7), p(8)),
        turn(r[0], 3),
        turn(r[1], 9),
    )
}

impl Element {
    /// Builds the element between reference nodes (positions `x`, rotations `r`).
    pub fn new(
        nodes: [usize; 2],
        section: Section,
        x: [&Vector3<f64>; 2],
        r: [&UnitQuaternion<f64>; 2],
    ) -> Self {
        let d = x[1] - x[0];
        let length = d.norm();
        let relative = r[0].conjugate() * r[1];
        let (phi0, half) = log_and_half(relative.quaternion());
        let lambda_m = matrix(&(r[0].quaternion() * half));
        Self {
            nodes,
            length,
            section,
            gamma0: lambda_m.transpose() * d / length,
            phi0,
            offsets: [UnitQuaternion::identity(); 2],
        }
    }

    /// Whether both end frames are the nodes' own (no corner offset): along a smooth beam,
    /// where the `f64` force skips the offsets' rotations (and the impact's contact its turns).
    pub fn straight(&self) -> bool {
        // Exactly the identity, as `Element::new` sets it (a corner's offset is far from it).
        self.offsets.iter().all(|o| o.i == 0.0 && o.j == 0.0 && o.k == 0.0)
    }

    /// Strains and the quantities the force needs, generic in the scalar.
    #[allow(clippy::type_complexity)]
    fn kinematics<T: RealField + Copy>(
        &self,
        x1: &Vector3<T>,
        x2: &Vector3<T>,
        q1: &Quaternion<T>,
        q2: &Quaternion<T>,
    ) -> (Strains<T>, Vector3<T>, Vector3<T>, Quaternion<T>) {
        let l0: T = cst(self.length);
        let relative = q1.conjugate() * q2;
        let (phi, half) = log_and_half(&relative);
        let gamma_full = turn(&(q1 * half).conjugate(), &(x2 - x1)) / l0;
        let gamma = gamma_full - self.gamma0.map(cst::<T>);
        let kappa = (phi - self.phi0.map(cst::<T>)) / l0;
        (Strains { gamma, kappa }, gamma_full, phi, half)
    }

    /// [`Self::kinematics`] in `f64` with unit quaternions (the rotations applied to vectors
    /// directly, no matrices; the same arithmetic up to round-off), from the node rotations:
    /// the strains, `gamma_full`, `phi`, the half rotation and the midpoint rotation.
    #[allow(clippy::type_complexity)]
    fn kinematics_f64(
        &self,
        x: [&Vector3<f64>; 2],
        r: [&UnitQuaternion<f64>; 2],
    ) -> (Strains<f64>, Vector3<f64>, Vector3<f64>, UnitQuaternion<f64>, UnitQuaternion<f64>) {
        let (q1, q2) = if self.straight() {
            (*r[0], *r[1])
        } else {
            (r[0] * self.offsets[0], r[1] * self.offsets[1])
        };
        let (phi, half) = log_and_half((q1.conjugate() * q2).quaternion());
        let half = UnitQuaternion::new_unchecked(half);
        let midpoint = q1 * half;
        let per_length = 1.0 / self.length;
        let gamma_full = midpoint.inverse_transform_vector(&(x[1] - x[0])) * per_length;
        let strains =
            Strains { gamma: gamma_full - self.gamma0, kappa: (phi - self.phi0) * per_length };
        (strains, gamma_full, phi, half, midpoint)
    }

    /// Strains at the current configuration.
    pub fn strains(&self, x: [&Vector3<f64>; 2], r: [&UnitQuaternion<f64>; 2]) -> Strains<f64> {
        self.kinematics_f64(x, r).0
    }

    /// Strain energy (J).
    pub fn energy(&self, x: [&Vector3<f64>; 2], r: [&UnitQuaternion<f64>; 2]) -> f64 {
        self.energy_of(&self.strains(x, r))
    }

    /// Strain energy (J) at the strains `s` (`l0 (Gamma . C_N Gamma + K . C_M K) / 2`).
    pub fn energy_of(&self, s: &Strains<f64>) -> f64 {
        let cn = self.section.force_stiffness();
        let cm = self.section.moment_stiffness();
        0.5 * self.length
            * (0..3).map(|i| cn[i] * s.gamma[i].powi(2) + cm[i] * s.kappa[i].powi(2)).sum::<f64>()
    }

    /// Internal force `[f_x1, f_th1, f_x2, f_th2]` (N, N m; moments in the nodal material
    /// frames), generic in the scalar; `q1`, `q2` are the node rotations.
    fn force_generic<T: RealField + Copy>(
        &self,
        x1: &Vector3<T>,
        x2: &Vector3<T>,
        q1: &Quaternion<T>,
        q2: &Quaternion<T>,
    ) -> SVector<T, 12> {
        let q1 = &(q1 * quaternion_to::<T>(&self.offsets[0]));
        let q2 = &(q2 * quaternion_to::<T>(&self.offsets[1]));
        let l0: T = cst(self.length);
        let (s, gamma_full, phi, half) = self.kinematics(x1, x2, q1, q2);
        let cn = self.section.force_stiffness();
        let cm = self.section.moment_stiffness();
        let n =
            Vector3::new(s.gamma.x * cst(cn[0]), s.gamma.y * cst(cn[1]), s.gamma.z * cst(cn[2]));
        let m =
            Vector3::new(s.kappa.x * cst(cm[0]), s.kappa.y * cst(cm[1]), s.kappa.z * cst(cm[2]));
        // The rotations applied to vectors and the Jacobians by cross products, as in
        // `force` (fewer products of dual numbers than through 3x3 matrices).
        let n_spatial = turn(&(q1 * half), &n);
        let c = n.cross(&gamma_full) * l0;
        let half_c = c * cst::<T>(0.5);
        let m_tilde = m + right_jacobian_transpose_times(&(phi * cst::<T>(0.5)), &half_c);
        let f_th2 = right_jacobian_inverse_transpose_times(&phi, &m_tilde);
        let f_th1 = turn(&half, &(c - turn(&half, &f_th2)));
        let mut f = SVector::<T, 12>::zeros();
        // Moments for variations of the node frames: with Lambda_end = Lambda_node O, a node
        // variation th gives the end variation O^T th, so the node moment is O times the end one.
        let o1 = quaternion_to::<T>(&self.offsets[0]);
        let o2 = quaternion_to::<T>(&self.offsets[1]);
        f.fixed_rows_mut::<3>(0).copy_from(&(-n_spatial));
        f.fixed_rows_mut::<3>(3).copy_from(&turn(&o1, &f_th1));
        f.fixed_rows_mut::<3>(6).copy_from(&n_spatial);
        f.fixed_rows_mut::<3>(9).copy_from(&turn(&o2, &f_th2));
        f
    }

    /// Internal force (N, N m): the generic force's formulas in `f64`, with rotations
    /// applied to vectors by the quaternions and the Jacobians by cross products (a Newton
    /// iteration of the 3D beam evaluates this for every element; the generic form builds five
    /// 3x3 matrices for it). The dual-number tangent differentiates the generic form; a test
    /// holds the two equal to round-off.
    pub fn force(&self, x: [&Vector3<f64>; 2], r: [&UnitQuaternion<f64>; 2]) -> SVector<f64, 12> {
        let (s, gamma_full, phi, half, midpoint) = self.kinematics_f64(x, r);
        let n = s.gamma.component_mul(&Vector3::from(self.section.force_stiffness()));
        let m = s.kappa.component_mul(&Vector3::from(self.section.moment_stiffness()));
        let n_spatial = midpoint * n;
        let c = n.cross(&gamma_full) * self.length;
        let m_tilde = m + right_jacobian_transpose_times(&(phi * 0.5), &(c * 0.5));
        let f_th2 = right_jacobian_inverse_transpose_times(&phi, &m_tilde);
        let f_th1 = half * (c - half * f_th2);
        let mut f = SVector::<f64, 12>::zeros();
        f.fixed_rows_mut::<3>(0).copy_from(&(-n_spatial));
        f.fixed_rows_mut::<3>(6).copy_from(&n_spatial);
        if self.straight() {
            f.fixed_rows_mut::<3>(3).copy_from(&f_th1);
            f.fixed_rows_mut::<3>(9).copy_from(&f_th2);
        } else {
            f.fixed_rows_mut::<3>(3).copy_from(&(self.offsets[0] * f_th1));
            f.fixed_rows_mut::<3>(9).copy_from(&(self.offsets[1] * f_th2));
        }
        f
    }

    /// The derivative of the strains `[Gamma; K]` with respect to `[dx1, th1, dx2, th2]` at a
    /// configuration (the rotations updated as `Lambda_i exp(th_i^)`, as for
    /// [`Element::force_and_tangent`]), exact by the same dual numbers: at the reference it
    /// turns a linear mode's nodal motion into its section strains (the modal method on a
    /// finite-element basis recovers stresses with it).
    pub fn strain_jacobian(
        &self,
        x: [&Vector3<f64>; 2],
        r: [&UnitQuaternion<f64>; 2],
    ) -> SMatrix<f64, 6, 12> {
        let mut jacobian = SMatrix::<f64, 6, 12>::zeros();
        for j in 0..12 {
            let (x1, x2, q1, q2) = seeded_along(x, r, j);
            let q1 = q1 * quaternion_to::<Dual64>(&self.offsets[0]);
            let q2 = q2 * quaternion_to::<Dual64>(&self.offsets[1]);
            let (s, ..) = self.kinematics(&x1, &x2, &q1, &q2);
            for (i, value) in s.gamma.iter().chain(s.kappa.iter()).enumerate() {
                jacobian[(i, j)] = value.eps;
            }
        }
        jacobian
    }

    /// Internal force and its exact derivative with respect to `[dx1, th1, dx2, th2]`, where
    /// the rotations are updated as `Lambda_i exp(th_i^)`: one column a pass, in dual numbers of
    /// that one direction.
    pub fn force_and_tangent(
        &self,
        x: [&Vector3<f64>; 2],
        r: [&UnitQuaternion<f64>; 2],
    ) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let mut value = SVector::<f64, 12>::zeros();
        let mut tangent = SMatrix::<f64, 12, 12>::zeros();
        for j in 0..12 {
            let (x1, x2, q1, q2) = seeded_along(x, r, j);
            let f = self.force_generic(&x1, &x2, &q1, &q2);
            for i in 0..12 {
                value[i] = f[i].re;
                tangent[(i, j)] = f[i].eps;
            }
        }
        (value, tangent)
    }
}
