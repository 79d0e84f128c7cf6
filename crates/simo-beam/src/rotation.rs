//! Rotations for the element, generic over the scalar so that the same code runs on `f64` and
//! on dual numbers (the element tangent is the forward-mode derivative of its internal force).
//!
//! Conventions: unit quaternions `q = (w, v)` map section axes to space; a rotation vector
//! `phi` has `exp(phi^)` with angle `|phi|`; the right Jacobian `J_r(phi)` satisfies
//! `d exp(phi^) = exp(phi^) (J_r(phi) d phi)^`.

use nalgebra::{Matrix3, Quaternion, RealField, UnitQuaternion, Vector3};

/// Below this squared angle the trigonometric coefficients are evaluated by their series
/// (truncation error ~ angle^6 / 1e5, below 1e-20 at this bound).
pub(crate) const SERIES_BELOW: f64 = 1e-4;

fn c<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

/// Skew matrix `a^` with `a^ b = a x b`.
pub fn skew<T: RealField + Copy>(a: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -a.z, a.y, a.z, z, -a.x, -a.y, a.x, z)
}

/// Rotation matrix of a quaternion that is unit to first order (the dual perturbations used for
/// the tangent are unit only to first order, which is all a first derivative needs).
pub fn matrix<T: RealField + Copy>(q: &Quaternion<T>) -> Matrix3<T> {
    UnitQuaternion::new_unchecked(*q).to_rotation_matrix().into_inner()
}

/// Rotation vector of the relative rotation `q` (any sign), with angle in `[0, pi]`, and the
/// half rotation `exp(phi^ / 2)` as a quaternion.
pub fn log_and_half<T: RealField + Copy>(q: &Quaternion<T>) -> (Vector3<T>, Quaternion<T>) {
    // q and -q are the same rotation: take w >= 0 so the angle is at most pi.
    let q = if q.w < T::zero() { -*q } else { *q };
    let (w, v) = (q.w, q.imag());
    let s2 = v.norm_squared();
    // angle / |v| = 2 atan2(|v|, w) / |v|, written in |v|^2 near zero so dual numbers stay finite.
    let ratio = if s2 < c(SERIES_BELOW) {
        log_ratio_series(s2, T::one() / w)
    } else {
        let s = s2.sqrt();
        c::<T>(2.0) * s.atan2(w) / s
    };
    // exp(phi/2) is the normalised mean of the identity and q (w >= 0 keeps 1 + w away from 0).
    let one_plus_w = T::one() + w;
    let inverse_norm = T::one() / (c::<T>(2.0) * one_plus_w).sqrt();
    let half = Quaternion::from_parts(one_plus_w * inverse_norm, v * inverse_norm);
    (v * ratio, half)
}

/// `2 atan2(|v|, w) / |v|` by its series in `x = |v|^2 / w^2` (from `s2 = |v|^2` and `1 / w`):
/// `2 / w (1 - x / 3 + x^2 / 5 - x^3 / 7)` by Horner's rule, for `s2` below [`SERIES_BELOW`].
#[inline(always)]
pub(crate) fn log_ratio_series<T: RealField + Copy>(s2: T, inverse_w: T) -> T {
    let x = s2 * inverse_w * inverse_w;
    let series = T::one() + x * (c::<T>(-1.0 / 3.0) + x * (c::<T>(1.0 / 5.0) - x * c(1.0 / 7.0)));
    (inverse_w + inverse_w) * series
}

/// [`inverse_coefficient`]'s series below [`SERIES_BELOW`]: `1/12 + a^2/720 + a^4/30240`.
#[inline(always)]
pub(crate) fn inverse_series<T: RealField + Copy>(a2: T) -> T {
    c::<T>(1.0 / 12.0) + a2 * (c::<T>(1.0 / 720.0) + a2 * c(1.0 / 30240.0))
}

/// [`jacobian_coefficients`]' series below [`SERIES_BELOW`]: `1/2 - a^2/24 + a^4/720` and
/// `1/6 - a^2/120 + a^4/5040`.
#[inline(always)]
pub(crate) fn jacobian_series<T: RealField + Copy>(a2: T) -> (T, T) {
    (
        c::<T>(0.5) + a2 * (c::<T>(-1.0 / 24.0) + a2 * c(1.0 / 720.0)),
        c::<T>(1.0 / 6.0) + a2 * (c::<T>(-1.0 / 120.0) + a2 * c(1.0 / 5040.0)),
    )
}

/// The coefficient of `phi^2` in `J_r(phi)^-1`: `1/a^2 - (1 + cos a)/(2 a sin a)`, a = |phi|.
fn inverse_coefficient<T: RealField + Copy>(a2: T) -> T {
    if a2 < c(SERIES_BELOW) {
        inverse_series(a2)
    } else {
        let a = a2.sqrt();
        T::one() / a2 - (T::one() + a.cos()) / (c::<T>(2.0) * a * a.sin())
    }
}

/// The coefficients of `-phi^` and `phi^2` in `J_r(phi)`: `(1 - cos a)/a^2`, `(a - sin a)/a^3`.
fn jacobian_coefficients<T: RealField + Copy>(a2: T) -> (T, T) {
    if a2 < c(SERIES_BELOW) {
        jacobian_series(a2)
    } else {
        let a = a2.sqrt();
        ((T::one() - a.cos()) / a2, (a - a.sin()) / (a2 * a))
    }
}

/// `J_r(phi)^-1 = I + phi^/2 + (1/a^2 - (1 + cos a)/(2 a sin a)) phi^2`, valid for a < pi.
pub fn right_jacobian_inverse<T: RealField + Copy>(phi: &Vector3<T>) -> Matrix3<T> {
    let coefficient = inverse_coefficient(phi.norm_squared());
    let k = skew(phi);
    Matrix3::identity() + k * c::<T>(0.5) + k * k * coefficient
}

/// `J_r(phi) = I - (1 - cos a)/a^2 phi^ + (a - sin a)/a^3 phi^2`.
pub fn right_jacobian<T: RealField + Copy>(phi: &Vector3<T>) -> Matrix3<T> {
    let (c1, c2) = jacobian_coefficients(phi.norm_squared());
    let k = skew(phi);
    Matrix3::identity() - k * c1 + k * k * c2
}

/// `J_r(phi)^T v = v + c1 phi x v + c2 phi x (phi x v)` (the transposed skew changes sign),
/// by cross products: the element's force needs only the product, not the matrix.
pub fn right_jacobian_transpose_times<T: RealField + Copy>(
    phi: &Vector3<T>,
    v: &Vector3<T>,
) -> Vector3<T> {
    let (c1, c2) = jacobian_coefficients(phi.norm_squared());
    let pv = phi.cross(v);
    v + pv * c1 + phi.cross(&pv) * c2
}

/// `J_r(phi)^-T v = v - phi x v / 2 + coefficient phi x (phi x v)`, by cross products.
pub fn right_jacobian_inverse_transpose_times<T: RealField + Copy>(
    phi: &Vector3<T>,
    v: &Vector3<T>,
) -> Vector3<T> {
    let coefficient = inverse_coefficient(phi.norm_squared());
    let pv = phi.cross(v);
    v - pv * c::<T>(0.5) + phi.cross(&pv) * coefficient
}

/// `v` turned by the quaternion `q = (w, u)`, unit to first order: `v + 2 w u x v + 2 u x (u x v)`
/// (the rotation matrix's product without the matrix; for dual numbers the same derivative,
/// the two agreeing on unit quaternions).
pub fn turn<T: RealField + Copy>(q: &Quaternion<T>, v: &Vector3<T>) -> Vector3<T> {
    let u = q.imag();
    let t = u.cross(v) * c::<T>(2.0);
    v + t * q.w + u.cross(&t)
}

/// `exp(phi^)` as a unit quaternion `(cos(a/2), sin(a/2)/a phi)` (f64 only; used by the
/// configuration update). A Newton correction's angle is small: below the series bound the
/// coefficients are Taylor series (`cos(a/2) = 1 - a^2/8 + a^4/384 - a^6/46080`,
/// `sin(a/2)/a = 1/2 - a^2/48 + a^4/3840 - a^6/645120`, truncation ~ a^8/1e7 < 1e-23),
/// without `sin` and `cos`.
#[inline(always)]
pub fn exp(phi: &Vector3<f64>) -> UnitQuaternion<f64> {
    let a2 = phi.norm_squared();
    if a2 >= SERIES_BELOW {
        return UnitQuaternion::from_scaled_axis(*phi);
    }
    let (w, s) = exp_series_coefficients(hht::fast::Separate, a2);
    UnitQuaternion::new_unchecked(Quaternion::from_parts(w, phi * s))
}

/// [`exp`]'s series below [`SERIES_BELOW`]: `(cos(a/2), sin(a/2)/a)` from `a2 = a^2`, by
/// Horner's rule in `m`'s multiply-adds.
#[inline(always)]
pub(crate) fn exp_series_coefficients<A: hht::fast::MulAdd>(m: A, a2: f64) -> (f64, f64) {
    let w =
        m.mul_add(-a2, m.mul_add(-a2, m.mul_add(-a2, 1.0 / 46080.0, 1.0 / 384.0), 1.0 / 8.0), 1.0);
    let s = m.mul_add(
        -a2,
        m.mul_add(-a2, m.mul_add(-a2, 1.0 / 645_120.0, 1.0 / 3840.0), 1.0 / 48.0),
        0.5,
    );
    (w, s)
}
