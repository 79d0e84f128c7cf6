//! The beam theory a scene needs, and where beam theory stops.
//!
//! A [`BeamSpec`] becomes a [`modal::Beam`] of either theory here, and only here: the modal
//! method takes the one [`choose`] picks, the fe method (whose Simo beam always has shear and
//! rotary inertia) the Timoshenko one for its reference quantities. The size of what
//! Euler-Bernoulli leaves out is [`correction`]; [`limits`] warns where no beam theory holds.

use super::Pulse;
use crate::error::ImpactError;
use crate::scene::{BeamSpec, TheoryName};
use modal::Beam;
use std::f64::consts::PI;

/// Below this relative frequency correction the plan keeps Euler-Bernoulli by default: nothing
/// the contact excites moves by more than round-off of the answers a tolerance can ask for.
pub const NEGLIGIBLE_CORRECTION: f64 = 1e-9;
/// An Euler-Bernoulli run warns when its correction reaches this (0.01 %).
pub const NOTABLE_CORRECTION: f64 = 1e-4;
/// Length over thickness below which no beam theory holds (validation/REFERENCES.md 1.6).
pub const MIN_SLENDERNESS: f64 = 3.0;
/// Flexural wavelength over thickness below which Timoshenko's dispersion leaves the exact one
/// of a layer (validation/REFERENCES.md 1.6).
pub const MIN_WAVELENGTH: f64 = 2.0;

/// The beam of `spec` as Euler-Bernoulli and as Timoshenko (shear coefficient 5/6 of a
/// rectangle, as the fe beam's section, G = E / (2 (1 + nu)), rotary inertia rho I).
///
/// # Errors
/// From `modal` for a value that is not finite and positive (checked before, not expected).
pub(crate) fn beams(spec: &BeamSpec) -> Result<(Beam, Beam), ImpactError> {
    let euler_bernoulli = Beam::rectangular(
        spec.youngs_modulus,
        spec.density,
        spec.width,
        spec.thickness,
        spec.length,
        spec.support.into(),
    )?;
    let shear_modulus = spec.youngs_modulus / (2.0 * (1.0 + spec.poisson_ratio));
    let area = spec.width * spec.thickness;
    let inertia = spec.width * spec.thickness.powi(3) / 12.0;
    let timoshenko = euler_bernoulli.with_shear(
        simo_beam::SHEAR_FACTOR_RECTANGLE * shear_modulus * area,
        spec.density * inertia,
    )?;
    Ok((euler_bernoulli, timoshenko))
}

/// The beam of `spec` in Saint-Venant torsion (validation/REFERENCES.md 1.9): G J with the
/// rectangle's exact torsion constant, rho Ip with Ip = (b t^3 + t b^3) / 12, the same ends.
///
/// # Errors
/// From `modal` for a value that is not finite and positive (checked before, not expected).
pub(crate) fn torsion(spec: &BeamSpec) -> Result<modal::Torsion, ImpactError> {
    let shear_modulus = spec.youngs_modulus / (2.0 * (1.0 + spec.poisson_ratio));
    let (j, _) = modal::rectangle_torsion(spec.width, spec.thickness);
    let (b, t) = (spec.width, spec.thickness);
    let polar = (b * t.powi(3) + t * b.powi(3)) / 12.0;
    Ok(modal::Torsion::new(
        shear_modulus * j,
        spec.density * polar,
        spec.length,
        spec.support.into(),
    )?)
}

/// The frequency (rad/s) the pulse excites most: a half-sine of the contact duration t_c has
/// its energy around pi / t_c.
fn pulse_frequency(pulse: &Pulse) -> f64 {
    PI / pulse.duration
}

/// Bending wavenumber (1/m) of `beam` at omega, Euler-Bernoulli: beta^4 = rho A omega^2 / EI.
fn wavenumber(beam: &Beam, omega: f64) -> f64 {
    (omega * (beam.mass_per_length() / beam.flexural_rigidity()).sqrt()).sqrt()
}

/// How much shear and rotary inertia lower the frequency the pulse excites most, relative:
/// the first-order Timoshenko correction (beta r)^2 (1 + E/(kG))/2 (r^2 = I/A), exact to first
/// order for pinned-pinned and for every support's high modes (validation/REFERENCES.md 1.6).
/// On the thick beams of validation/REFERENCES.md 1.6 it is the size of the difference the
/// contacts show between the theories.
pub(crate) fn correction(spec: &BeamSpec, beam: &Beam, pulse: &Pulse) -> f64 {
    let beta = wavenumber(beam, pulse_frequency(pulse));
    let r2 = spec.thickness * spec.thickness / 12.0;
    let shear = beam.shear().map_or(0.0, |s| s.rigidity);
    let rigidity_ratio =
        if shear > 0.0 { spec.youngs_modulus * spec.width * spec.thickness / shear } else { 0.0 };
    0.5 * beta * beta * r2 * (1.0 + rigidity_ratio)
}

/// The scene's name of `beam`'s theory.
pub(crate) fn name(beam: &Beam) -> TheoryName {
    match beam.theory() {
        modal::Theory::EulerBernoulli => TheoryName::EulerBernoulli,
        modal::Theory::Timoshenko => TheoryName::Timoshenko,
    }
}

/// The modal method's beam: as asked, else Timoshenko unless its correction is negligible,
/// with the reason; and, where Euler-Bernoulli was asked for and Timoshenko's correction is
/// notable, the Timoshenko beam and that correction, for the run to measure what the theory
/// leaves out (the correction is a frequency's shift, not the results': on the paper's tip
/// 4.4e-2 against 4.6e-4 measured).
pub(crate) fn choose(
    asked: Option<TheoryName>,
    spec: &BeamSpec,
    (euler_bernoulli, timoshenko): (Beam, Beam),
    pulse: &Pulse,
    reasons: &mut Vec<String>,
) -> (Beam, Option<(Beam, f64)>) {
    let delta = correction(spec, &timoshenko, pulse);
    let omega = pulse_frequency(pulse);
    let size = format!("shear and rotary inertia lower the frequency the pulse excites most (pi/t_c = {omega:.4e} rad/s) by {delta:.2e} of itself (first-order Timoshenko correction)");
    match asked {
        Some(TheoryName::Timoshenko) => {
            reasons.push(format!("Timoshenko modes, as asked: {size}"));
            (timoshenko, None)
        }
        Some(TheoryName::EulerBernoulli) => {
            reasons.push(format!("Euler-Bernoulli modes, as asked: {size}"));
            if delta >= NOTABLE_CORRECTION {
                (euler_bernoulli, Some((timoshenko, delta)))
            } else {
                (euler_bernoulli, None)
            }
        }
        None if delta < NEGLIGIBLE_CORRECTION => {
            reasons.push(format!(
                "Euler-Bernoulli modes (default): {size}, below {NEGLIGIBLE_CORRECTION:e}"
            ));
            (euler_bernoulli, None)
        }
        None => {
            reasons.push(format!(
                "Timoshenko modes (default): {size}; both branches of the spectrum are kept"
            ));
            (timoshenko, None)
        }
    }
}

/// Warnings where the scene leaves what a beam model can say: a beam too stubby for any beam
/// theory, and a pulse whose flexural wavelength is not long against the thickness.
pub(crate) fn limits(spec: &BeamSpec, beam: &Beam, pulse: &Pulse, warnings: &mut Vec<String>) {
    let slenderness = spec.length / spec.thickness;
    if slenderness < MIN_SLENDERNESS {
        warnings.push(format!(
            "beam.length / beam.thickness = {slenderness:.3}: below {MIN_SLENDERNESS} no beam theory holds (a deep beam is a two-dimensional solid; validation/REFERENCES.md 1.6): the results are a beam model's, not the body's"
        ));
    }
    let wavelength = 2.0 * PI / wavenumber(beam, pulse_frequency(pulse));
    let ratio = wavelength / spec.thickness;
    if ratio < MIN_WAVELENGTH {
        warnings.push(format!(
            "the flexural wavelength at the frequency the pulse excites most is {wavelength:.3e} m, {ratio:.3} times beam.thickness: below {MIN_WAVELENGTH} beam theories leave the exact waves of a layer (validation/REFERENCES.md 1.6), and the contact sees the beam as a thick solid"
        ));
    }
}
