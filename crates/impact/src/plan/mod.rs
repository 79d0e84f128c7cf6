//! Planning: validate a scene and choose the model it needs, with the reasons.
//!
//! [`Plan::new`] reads the scene once, in order: the ball, the impact speed, the struck body,
//! the contact law ([`crate::Law`]), then the method ([`Method`]: a rigid half-space, the modal
//! beam of [`ModalPlan`] or the finite elements of [`FePlan`]), the contact step, the end time and
//! the output interval. Every choice leaves a reason in the [`PlanSummary`]. A plan is made only
//! by [`Plan::new`], so a solver never meets an unvalidated one.
//!
//! The constants here are the defaults a scene gets when it leaves a setting out; each says
//! where its value comes from.

mod fe;
mod modal;
mod structure;
mod theory;

pub(crate) use fe::Attachment;
pub use fe::{
    FePlan, FE_ALPHA, FE_ELEMENTS_PER_WAVELENGTH, FE_FREE_STEP_RATIO, FE_GROWTH, FE_LADDER_END,
    FE_LADDER_START, FE_SAMPLES_PER_PULSE,
};
pub use modal::{ModalBasis, ModalPlan, MODAL_LADDER_END, MODE_CUTOFF};
pub use structure::FeBasis;
pub use theory::{MIN_SLENDERNESS, MIN_WAVELENGTH, NEGLIGIBLE_CORRECTION, NOTABLE_CORRECTION};

/// A beam scene's window without `solver.end_time` (s): the paper's 5 ms.
pub(crate) const DEFAULT_END_TIME: f64 = 0.005;

use crate::error::{bounded, invalid, not_negative, positive, range, show, ImpactError};
use crate::law::{Law, LawContext};
use crate::scene::{
    BallSpec, BeamSpec, ImpactSpec, LawName, MethodName, ModalBasisName, Scene, SolverSpec,
    SupportName, TheoryName,
};
use hertz::{HalfSpaceImpact, Hertz, Material};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Equal intervals of the beam whose ends (and the impact point) a field holds.
pub const FIELD_POINTS: usize = 64;
/// The most values a field may hold (8 bytes each): 400 MB.
pub const MAX_FIELD_VALUES: f64 = 5e7;

/// The default output's instants over the window (`solver.output_interval` = end_time over
/// this); a structure's modal maxima are read no sparser whatever the output asks.
pub(crate) const DEFAULT_OUTPUTS: f64 = 2000.0;

/// Standard gravity (m/s^2).
pub const GRAVITY: f64 = 9.81;
/// Default time steps per estimated contact duration: the modal method's largest contact
/// step. With uniform steps the scheme is second order: on the paper's tip scene (64 modes,
/// 5 ms, gravity off, 27 contacts) the energy balance error is 1.6e-5, 4.1e-6, 1.0e-6, 2.6e-7
/// of the initial energy at 200, 400, 800, 1600 steps, almost all of it made in the first
/// steps after onset. The adaptive step (the default) refines there and keeps the error at
/// 4e-7 with 6000 steps in all where uniform steps needed 1000 per pulse (24000); see
/// [`DEFAULT_ENERGY_TOLERANCE`] and the impact tests. This is the uniform step's default; the
/// adaptive step's is [`DEFAULT_ADAPTIVE_SAMPLES_PER_PULSE`].
pub const DEFAULT_SAMPLES_PER_PULSE: usize = 200;
/// The adaptive step's largest step, in steps per estimated contact duration: the estimate is
/// the first contact's, and the later contacts of a chattering sequence are much weaker (the
/// paper's tip: 39 N, 7 N, then 0.1-14 N after a 782 N first one), so the energy mismatch
/// lets them take steps above the first contact's. Measured on the paper's tip scene (256
/// modes, 5 ms, gravity off): capping at 100 per duration instead of 200 takes 23 % fewer
/// contact steps (3929 against 5071), and the first 29 contacts stay within 1.3e-4 of a run
/// on 2000 uniform steps per duration, as they were (1.9e-4). The energy balance error grows
/// with the longer steps (64 modes: 9.0e-7 of the initial energy against 4.3e-7), within
/// the 1e-6 the scheme is held to; a cap of 50 would cut the steps by 30 % but reach 1.9e-6.
pub const DEFAULT_ADAPTIVE_SAMPLES_PER_PULSE: usize = 100;
/// Default allowed energy mismatch of the modal method's adaptive contact step, as a fraction
/// of the impact energy per estimated contact duration.
pub const DEFAULT_ENERGY_TOLERANCE: f64 = 1e-6;
/// The modal method's adaptive contact step starts each contact at the plan's step /
/// 2^FINEST_LEVEL and stays within [step / 2^FINEST_LEVEL, step]: by default from 1/12800 to
/// 1/100 of the estimated contact duration.
pub const FINEST_LEVEL: usize = 7;
/// The most rows a history may hold in free flight (end time / output interval): 1e7 rows of
/// eleven 8-byte columns, about 0.9 GB. A finer history is refused up front, with its size.
pub const MAX_HISTORY_ROWS: f64 = 1e7;

/// The fewest steps of an fe run beyond which the plan warns of its length: each step solves
/// the whole beam (on the paper's tip at 256 elements, about 8 us a step planar and 37 us in
/// 3D on a 2-core machine, validation/REFERENCES.md 1.9), so minutes or more.
pub const LONG_RUN_STEPS: f64 = 1e7;

/// The estimated seconds of an fe run beyond which the plan warns of its length, from its
/// steps and elements at 55 ns a step and element planar (a long beam meshed for a short
/// pulse: many elements, each step all of them).
pub const LONG_RUN_SECONDS: f64 = 60.0;

/// Seconds a step takes per element on the 2-core machine, planar and 3D, on the large meshes
/// a long run has: planar, 31 ns on the paper's tip at 256 elements, 55 ns at 6199 (a 3 m
/// strip struck by a 0.5 mm ball: 21076 steps in 7.2 s), as the state outgrows the caches;
/// 3D 145 ns at 256 (validation/REFERENCES.md 1.9), taken in the same proportion.
const STEP_SECONDS: (f64, f64) = (55e-9, 55e-9 * 145.0 / 31.0);

/// How the long run's warning starts (see [`Plan::long_run`]).
const LONG_RUN: &str = "a long run: ";

/// Warns where an fe run to `end_time` takes more than [`LONG_RUN_STEPS`] steps or about
/// [`LONG_RUN_SECONDS`], with what sets the steps and the elements and what shortens the run
/// (a ball of a micrometre on a metre of beam: a contact of nanoseconds, a step of a fraction
/// of it; a long beam under a short pulse: elements of a fraction of a millimetre).
fn long_run(fe: &FePlan, end_time: f64, estimated_duration: f64, warnings: &mut Vec<String>) {
    let steps = end_time / fe.free_time_step;
    let elements = fe
        .nodes
        .len()
        .saturating_sub(1)
        .max(fe.structure.as_ref().map_or(0, |st| st.model.mesh().elements.len()));
    let per = if fe.three_d() { STEP_SECONDS.1 } else { STEP_SECONDS.0 };
    let seconds = steps * elements as f64 * per;
    if steps > LONG_RUN_STEPS || seconds > LONG_RUN_SECONDS {
        let samples = fe.samples_per_pulse;
        warnings.push(format!(
            "{LONG_RUN}solver.end_time = {} s takes at least {steps:.1e} HHT steps of up to {:.3e} s on {elements} elements, about {} on a 2-core machine (the contact step is 1/{samples} of the estimated contact duration {estimated_duration:.3e} s, which the ball, the face and the contact law set; each step solves all the elements, about 8 us planar and 37 us in 3D at 256 of them); a shorter solver.end_time, fewer solver.samples_per_pulse, a longer solver.time_step out of contact, or fewer elements shortens it",
            show(end_time),
            fe.free_time_step,
            duration_words(seconds),
        ));
    }
}

/// A run's estimated duration in words: seconds, minutes or hours.
fn duration_words(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.0} s")
    } else if seconds < 7200.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}
/// Bytes a history row takes (its eleven f64 columns).
const HISTORY_ROW_BYTES: f64 = 88.0;
/// The most steps per estimated contact duration: a contact then takes up to a million
/// steps; beyond it a run would take hours for no accuracy the scheme can deliver.
pub const MAX_SAMPLES_PER_PULSE: usize = 1_000_000;

/// The auto plan takes the finite-element method when the ball could bend the beam by more
/// than this fraction of its length; the modal report warns beyond it.
pub const LARGE_DEFLECTION: f64 = 0.1;

/// How the struck body is modelled.
#[derive(Debug, Clone, PartialEq)]
pub enum Method {
    /// A massive half-space: no beam, a rigid-backed Hertz contact.
    HalfSpace,
    /// A beam by its Euler-Bernoulli modes (Goldsmith's method).
    Modal(ModalPlan),
    /// A beam by geometrically exact finite elements (Simo) and HHT-alpha.
    Fe(FePlan),
}

/// Which method a plan chose, as the report names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodKind {
    /// A massive half-space.
    HalfSpace,
    /// Goldsmith's modal method.
    Modal,
    /// The geometrically exact finite-element method.
    Fe,
}

impl MethodKind {
    /// The name the report and the scene file use.
    pub fn as_str(self) -> &'static str {
        match self {
            MethodKind::HalfSpace => "half-space",
            MethodKind::Modal => "modal",
            MethodKind::Fe => "fe",
        }
    }
}

impl std::fmt::Display for MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Method {
    /// Which method this is.
    pub fn kind(&self) -> MethodKind {
        match self {
            Method::HalfSpace => MethodKind::HalfSpace,
            Method::Modal(_) => MethodKind::Modal,
            Method::Fe(_) => MethodKind::Fe,
        }
    }
}

/// The plan's summary for the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanSummary {
    /// The method chosen.
    pub method: MethodKind,
    /// Number of modes (0 unless modal).
    pub modes: usize,
    /// Number of finite elements (0 unless fe).
    pub elements: usize,
    /// Time step in contact (s): the largest of the modal method's adaptive step, the
    /// smallest of the fe method's.
    pub time_step: f64,
    /// The contact law.
    pub contact_law: LawName,
    /// The modal method's beam theory; absent for the fe method (its geometrically exact
    /// beam always has shear and rotary inertia) and a half-space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam_theory: Option<TheoryName>,
    /// Whether a `[structure]` was struck: the report's positions (of its stresses, twists and
    /// field) are then arc lengths s along its chain of segments, not x along a beam.
    #[serde(default)]
    pub structure: bool,
    /// Why each choice was made.
    pub reasons: Vec<String>,
}

/// A validated scene with every choice made; see [`Plan::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub(crate) name: String,
    pub(crate) method: Method,
    pub(crate) law: Law,
    /// Ball mass (kg).
    pub(crate) ball_mass: f64,
    /// Ball radius (m).
    pub(crate) ball_radius: f64,
    /// Impact speed (m/s).
    pub(crate) speed: f64,
    /// Gravity on the ball toward the beam (m/s^2), 0 if off.
    pub(crate) gravity: f64,
    /// Simulated time (s).
    pub(crate) end_time: f64,
    /// Time step in contact (s), as in [`PlanSummary::time_step`].
    pub(crate) time_step: f64,
    /// The modal method's adaptive contact step: its energy tolerance, `None` for uniform
    /// steps (and for the fe method).
    pub(crate) energy_tolerance: Option<f64>,
    /// History interval in free flight (s).
    pub(crate) output_interval: f64,
    /// Estimated duration of the first contact on a rigid support (s).
    pub(crate) estimated_duration: f64,
    /// The struck beam's thickness (m), none on a half-space.
    pub(crate) thickness: Option<f64>,
    /// The struck beam's width (m), none on a half-space.
    pub(crate) width: Option<f64>,
    /// Poisson's ratios of the ball and of the struck body (-).
    pub(crate) poisson_ratios: [f64; 2],
    /// The beam's yield stress (Pa), if given.
    pub(crate) beam_yield_stress: Option<f64>,
    /// Whether the run records the beam's field ([`Plan::with_field`]).
    pub(crate) field: bool,
    /// The beam's first elastic mode's period (s) (Timoshenko for the fe method), none on a half-space or
    /// a beam without one.
    pub(crate) first_period: Option<f64>,
    pub(crate) summary: PlanSummary,
    pub(crate) warnings: Vec<String>,
}

/// The first contact as if the struck body were rigid: the scale of steps and tolerances.
#[derive(Debug, Clone, Copy)]
struct Pulse {
    /// Ball mass (kg).
    ball_mass: f64,
    /// Impact speed (m/s).
    speed: f64,
    /// Contact duration on a rigid support (s).
    duration: f64,
    /// Largest approach on a rigid support (m).
    max_approach: f64,
    /// Whether `duration` is a damped contact's (twice its rise to the peak), not Hertz's.
    damped: bool,
}

impl Pulse {
    /// Where `duration` comes from, for the plan's reasons.
    fn source(&self) -> &'static str {
        if self.damped {
            "twice Hunt-Crossley's rise to its peak, rigid support"
        } else {
            "Hertz, rigid support"
        }
    }

    /// The fastest frequency (rad/s) the impact makes a section of bending stiffness
    /// `rigidity` EI (N m^2) and mass `mass` rho A (kg/m) answer at: omega t_c = MODE_CUTOFF,
    /// or [`modal::LOCAL_CUTOFF`] times the contact's local frequency where that is higher (a
    /// ball heavy against the beam meets its local response faster than its own pulse). The
    /// modes are kept to it, and the meshes are sized for it.
    fn fastest(&self, rigidity: f64, mass: f64) -> f64 {
        let local = modal::section_local_frequency(
            (rigidity, mass),
            (self.ball_mass, self.speed, self.max_approach),
        );
        (MODE_CUTOFF / self.duration).max(modal::LOCAL_CUTOFF * local)
    }

    /// The duration whose omega t_c = MODE_CUTOFF is [`Pulse::fastest`] (s): the pulse's own
    /// but for a heavy ball, the time scale the meshes are sized for.
    fn sized(&self, rigidity: f64, mass: f64) -> f64 {
        MODE_CUTOFF / self.fastest(rigidity, mass)
    }
}

/// A material from its fields under `prefix` (`ball`, `beam`, `half_space`).
fn material(
    prefix: &str,
    e: f64,
    nu: f64,
    yield_stress: Option<f64>,
) -> Result<Material, ImpactError> {
    bounded(&format!("{prefix}.youngs_modulus"), e, range::MODULUS, "Pa")?;
    if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(invalid(&format!("{prefix}.poisson_ratio"), nu, "must be in (-1, 0.5)"));
    }
    // The contact sees E / (1 - nu^2): near nu = -1 it grows without bound (1e17 Pa for
    // steel at -0.999999), so it is held to the same range as a modulus.
    let plane_strain = e / (1.0 - nu * nu);
    if plane_strain > range::MODULUS.1 {
        return Err(invalid(
            &format!("{prefix}.poisson_ratio"),
            nu,
            &format!(
                "makes the contact modulus E / (1 - nu^2) = {} Pa, above {} Pa; allowed: -1 < poisson_ratio < 0.5 with E / (1 - nu^2) within the moduli range",
                show(plane_strain),
                show(range::MODULUS.1)
            ),
        ));
    }
    let m = Material::new(e, nu)?;
    match yield_stress {
        Some(y) => {
            bounded(&format!("{prefix}.yield_stress"), y, range::MODULUS, "Pa")?;
            Ok(m.with_yield_stress(y)?)
        }
        None => Ok(m),
    }
}

/// The ball's material, radius (m) and mass (kg); a mass that disagrees with the density is
/// used as given, with a warning.
fn ball(b: &BallSpec, warnings: &mut Vec<String>) -> Result<(Material, f64, f64), ImpactError> {
    let radius = bounded("ball.radius", b.radius, range::LENGTH, "m")?;
    let density = bounded("ball.density", b.density, range::DENSITY, "kg/m^3")?;
    let ball_material = material("ball", b.youngs_modulus, b.poisson_ratio, b.yield_stress)?;
    let volume = 4.0 / 3.0 * PI * radius.powi(3);
    let mass = match b.mass {
        Some(m) => {
            bounded("ball.mass", m, range::MASS, "kg")?;
            let implied = m / volume;
            if !(0.8..=1.25).contains(&(implied / density)) {
                warnings.push(format!(
                    "ball.mass = {m} kg with ball.radius = {radius} m implies a density of {implied:.4e} kg/m^3, \
                     not ball.density = {density} kg/m^3; the mass is used as given"
                ));
            }
            m
        }
        None => density * volume,
    };
    Ok((ball_material, radius, mass))
}

/// Impact speed (m/s) from exactly one of `drop_height` and `speed`.
fn impact_speed(impact: &ImpactSpec) -> Result<f64, ImpactError> {
    match (impact.drop_height, impact.speed) {
        (Some(h), None) => {
            let (lo, hi) = range::SPEED;
            let heights = (lo * lo / (2.0 * GRAVITY), hi * hi / (2.0 * GRAVITY));
            Ok((2.0 * GRAVITY * bounded("impact.drop_height", h, heights, "m")?).sqrt())
        }
        (None, Some(v)) => bounded("impact.speed", v, range::SPEED, "m/s"),
        (Some(_), Some(_)) => Err(ImpactError::Inconsistent(
            "impact: give exactly one of drop_height (m) and speed (m/s), not both".into(),
        )),
        (None, None) => Err(ImpactError::Inconsistent(
            "impact: give one of drop_height (m) or speed (m/s)".into(),
        )),
    }
}

/// What the ball strikes.
#[derive(Clone, Copy)]
enum Struck<'s> {
    HalfSpace,
    Beam(&'s BeamSpec),
    Structure(&'s crate::scene::StructureSpec),
}

/// The struck body's material and what it is: exactly one of `[beam]`, `[half_space]` and
/// `[structure]`.
fn struck_body(scene: &Scene) -> Result<(Material, Struck<'_>), ImpactError> {
    match (&scene.beam, &scene.half_space, &scene.structure) {
        (Some(beam), None, None) => Ok((
            material("beam", beam.youngs_modulus, beam.poisson_ratio, beam.yield_stress)?,
            Struck::Beam(beam),
        )),
        (None, Some(hs), None) => Ok((
            material("half_space", hs.youngs_modulus, hs.poisson_ratio, hs.yield_stress)?,
            Struck::HalfSpace,
        )),
        (None, None, Some(st)) => {
            if let Some(rho) = st.section.density {
                bounded("structure.section.density", rho, range::DENSITY, "kg/m^3")?;
            }
            let (Some(e), Some(nu)) = (st.section.youngs_modulus, st.section.poisson_ratio) else {
                return Err(ImpactError::Inconsistent("structure.section: give youngs_modulus (Pa) and poisson_ratio (the ball's contact needs the material), with density, width and thickness".into()));
            };
            // The yield stress is the structure's own key, not its section's.
            if let Some(y) = st.yield_stress {
                bounded("structure.yield_stress", y, range::MODULUS, "Pa")?;
            }
            Ok((material("structure.section", e, nu, st.yield_stress)?, Struck::Structure(st)))
        }
        (None, None, None) => Err(ImpactError::Inconsistent(
            "the scene needs a [beam], a [half_space] or a [structure] to strike".into(),
        )),
        _ => Err(ImpactError::Inconsistent(
            "give one of [beam], [half_space] and [structure], not several".into(),
        )),
    }
}

/// `solver.tolerance`, checked: a relative error in (0, 1).
fn checked_tolerance(tolerance: f64) -> Result<f64, ImpactError> {
    if tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0 {
        Ok(tolerance)
    } else {
        Err(invalid("solver.tolerance", tolerance, "must be a relative error, 0 < tolerance < 1"))
    }
}

/// A carried `[beam]`'s modal plan on its own modes: the `[structure]` it is
/// ([`structure::lowered`]), its errors in the `[beam]`'s words.
fn own_modes(
    scene: &Scene,
    beam: &BeamSpec,
    position: f64,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<ModalPlan, ImpactError> {
    let (mut lowered, spec) = structure::lowered(scene, beam, position, pulse);
    // Planned as the modal method's, whichever method the scene names (`auto`: its checks
    // refuse what the modes cannot carry, and the caller falls back to the fe method).
    lowered.solver.method = MethodName::Modal;
    // The lowered scene's impact.at is the [beam]'s impact.position: named as written.
    structure::modal_plan(&lowered, &spec, pulse, (reasons, warnings))
        .map_err(|e| match e {
            ImpactError::InvalidField { field, value, allowed } if field == "impact.at" => {
                ImpactError::InvalidField {
                    field: "impact.position".into(),
                    value,
                    allowed,
                }
            }
            // A mechanism in the [beam]'s words: its supports and springs (along z).
            ImpactError::Inconsistent(m) if m.starts_with("the structure is a mechanism") => {
                let free = m.split(" leave ").nth(1).and_then(|r| r.split(' ').next());
                let name = SupportName::NAMES
                    .iter()
                    .find(|(_, s, _)| *s == beam.support)
                    .map_or("", |(n, ..)| n);
                ImpactError::Inconsistent(format!("beam.support = \"{name}\" with its springs (along z, about the width axis): on its own modes, those of its 3D finite-element beam, {} rigid-body motion(s) stay free, which the modal method would take linearised at rest; hold the beam by its supports, or strike it by solver.method = \"fe\"", free.unwrap_or("some")))
            }
            // Its mesh is the lowering's, not a key of the [beam]'s.
            ImpactError::InvalidField { field, value, .. }
                if field.starts_with("structure.segment[") && field.ends_with(".elements") =>
            {
                ImpactError::Inconsistent(format!("the [beam]'s own modes would be solved on {value} elements between two of its attachments (a sixteenth of the shortest wave the impact excites), more than 100000: strike it by solver.method = \"fe\", whose mesh covers only where the waves reach within the window (a window short enough for it: its default mesh is refused beyond 100000 elements too)"))
            }
            // Its springs are the [beam]'s, in order.
            ImpactError::InvalidField { field, value, allowed }
                if field.starts_with("structure.spring[") =>
            {
                ImpactError::InvalidField {
                    field: field.replacen("structure.spring[", "beam.spring[", 1),
                    value,
                    allowed,
                }
            }
            e => e,
        })
}

/// Whether the scene sets a key of the fe method only (`tolerance` is both methods').
fn fe_keys(s: &SolverSpec) -> bool {
    s.elements.is_some()
        || s.element_size.is_some()
        || s.alpha.is_some()
        || s.time_step.is_some()
        || s.fe_model.is_some()
}

/// The auto plan's word where the beam has no static stiffness to bound its bending by.
const FREE_BODY: &str = "a free body (no static stiffness to bound its bending by sqrt(m V^2 / k)): the run warns if its largest displacement passes the small-deflection range";

/// Why a free-free [beam] struck off its centreline takes its own modes (see `beam_method`).
const FREE_OFF_CENTRE_BASIS: &str = "modes from the beam's finite elements (the default for a free-free beam struck off its centreline): the [structure] it is (one member, a node at the impact point), its rigid-body motions taken out by inertia relief, so that the truncated modes' static share (bending and torsion) is carried; the uniform beam's analytic modes have none on a free body, and their twist rate's series reads the torque's jump at the struck section as its mean (a review's strip, 10 mm off at 0.5 m: the first peak force 2.8 % high, the torsion shear 6.0e4 against 2.35e7 Pa); solver.modal_basis = \"analytic\" (or solver.modes, beam_theory) takes those, warned";

/// The method asked, with `auto` read as `modal` where `solver.modal_basis` (a modal-only key)
/// is given, saying so.
fn modal_basis_implies_modal(s: &SolverSpec, reasons: &mut Vec<String>) -> MethodName {
    if s.method == MethodName::Auto && s.modal_basis.is_some() {
        reasons.push("method modal (auto): solver.modal_basis given".into());
        MethodName::Modal
    } else {
        s.method
    }
}

/// Keys of one method given with the other.
fn check_method_keys(s: &SolverSpec) -> Result<(), ImpactError> {
    if fe_keys(s) && (s.method == MethodName::Modal || s.modal_basis.is_some()) {
        return Err(ImpactError::Inconsistent(
            "solver.elements, element_size, alpha, time_step and fe_model belong to method = \"fe\"; the modal method takes solver.modes (or solver.tolerance)".into(),
        ));
    }
    if s.method == MethodName::Fe && s.modal_basis.is_some() {
        return Err(ImpactError::Inconsistent(
            "solver.modal_basis belongs to method = \"modal\" (where its modes come from); the fe method models the whole beam".into(),
        ));
    }
    if s.method == MethodName::Fe && s.modes.is_some() {
        return Err(ImpactError::Inconsistent(
            "solver.modes belongs to method = \"modal\"; the fe method takes solver.elements"
                .into(),
        ));
    }
    Ok(())
}

/// A half-space takes no beam resolution.
fn half_space(s: &SolverSpec, reasons: &mut Vec<String>) -> Result<Method, ImpactError> {
    if s.method == MethodName::Fe
        || fe_keys(s)
        || s.modes.is_some()
        || s.tolerance.is_some()
        || s.residual_flexibility.is_some()
        || s.plain_stress_series.is_some()
        || s.beam_theory.is_some()
        || s.modal_basis.is_some()
    {
        return Err(ImpactError::Inconsistent("a [half_space] scene needs no solver.method = \"fe\", elements, alpha, time_step, tolerance, modes, residual_flexibility, plain_stress_series, beam_theory nor modal_basis: the block is rigid".into()));
    }
    reasons.push(
        "massive half-space: no beam model, the ball meets a rigid-backed Hertz contact".into(),
    );
    Ok(Method::HalfSpace)
}

/// A beam: its checks, then the modal or the finite-element method, as asked or as the
/// largest deflection the ball's energy could cause allows.
fn beam_method(
    scene: &Scene,
    beam: &BeamSpec,
    pulse: &Pulse,
    reasons: &mut Vec<String>,
    warnings: &mut Vec<String>,
) -> Result<Method, ImpactError> {
    let s = &scene.solver;
    let length = bounded("beam.length", beam.length, range::LENGTH, "m")?;
    bounded("beam.width", beam.width, range::LENGTH, "m")?;
    bounded("beam.thickness", beam.thickness, range::LENGTH, "m")?;
    // A section larger than the span is no beam: neither method answers for it (a micrometre
    // strip of the paper's 25 x 5 mm section had panicked in the stress recovery, a review's).
    for (field, size) in [("beam.thickness", beam.thickness), ("beam.width", beam.width)] {
        if size > length {
            return Err(invalid(
                field,
                format!("{size:e}"),
                &format!("must be at most beam.length = {length:e} m: a section larger than its span is not a beam (check the three sizes, in metres; a block struck by the ball is a [half_space])"),
            ));
        }
    }
    bounded("beam.density", beam.density, range::DENSITY, "kg/m^3")?;
    let both = theory::beams(beam)?;
    // Shear adds to the static flexibility: the Timoshenko beam's is the closer one.
    let m = both.1;
    theory::limits(beam, &m, pulse, warnings);
    let position = scene.impact.position.ok_or_else(|| {
        ImpactError::Inconsistent("impact.position (m) is required with a [beam]".into())
    })?;
    if !(position.is_finite() && (0.0..=length).contains(&position)) {
        return Err(invalid(
            "impact.position",
            position,
            &format!("must be on the beam, 0 <= position <= beam.length = {length} (m)"),
        ));
    }
    // On a support itself neither method moves the point: the modal run had answered a ball
    // bouncing off a rigid face with a beam's stresses of a few pascals, where the fe method
    // refused it (a review's). Refused for both, by where it is.
    let [first, last] = beam.support.ends();
    let held: Vec<f64> = [(0.0, first), (length, last)]
        .into_iter()
        .filter(|(_, s)| *s != simo_beam::Support::Free)
        .map(|(x, _)| x)
        .collect();
    if held.iter().any(|x| (position - x).abs() <= 1e-12 * length) {
        let name = SupportName::NAMES.iter().find(|(_, s, _)| *s == beam.support);
        let places: Vec<String> = held.iter().map(|x| format!("x = {x} m")).collect();
        return Err(ImpactError::Inconsistent(format!(
            "impact.position = {position} m is on a support of the beam (beam.support = \"{}\"): the ball would meet a rigid face there; strike the beam away from its supports ({})",
            name.map_or("", |(n, ..)| n),
            places.join(" and ")
        )));
    }
    free_end(beam, position, scene.ball.radius, pulse, warnings);
    if scene.impact.at.is_some() || scene.impact.direction.is_some() {
        return Err(ImpactError::Inconsistent("impact.at and impact.direction belong to a [structure]; a [beam] takes impact.position (m from x = 0) and is struck on its thickness face".into()));
    }
    let offset = offset(beam.width, scene.impact.offset, scene.ball.radius, pulse, warnings)?;
    let attachments = attachments(beam, position, scene.ball.radius, pulse, (reasons, warnings))?;
    let torsion = if offset == 0.0 { None } else { Some(theory::torsion(beam)?) };
    let damping = beam.modal_damping.unwrap_or(0.0);
    if !(damping.is_finite() && (0.0..1.0).contains(&damping)) {
        return Err(invalid("beam.modal_damping", damping, "must be a damping ratio in [0, 1)"));
    }
    // The deflection if the ball's whole kinetic energy went into static bending at the
    // impact point, w = sqrt(m V^2 f): an upper bound that decides whether small-deflection
    // theory can hold.
    let twist = torsion.as_ref().and_then(|t| t.static_flexibility(position)).unwrap_or(0.0);
    let flexibility = m.static_flexibility(position).unwrap_or(0.0) + offset * offset * twist;
    let deflection = (pulse.ball_mass * pulse.speed * pulse.speed * flexibility).sqrt();
    let large = deflection > LARGE_DEFLECTION * length;
    let method = modal_basis_implies_modal(s, reasons);
    if s.method == MethodName::Modal {
        reasons.push("method modal, as asked".into());
    }
    // A free-free beam struck off its centreline: the uniform beam's analytic modes have no
    // static flexibility to add the truncated modes' share by (it is a free body), and the
    // torque e F jumps across the struck section, where their twist rate's series reads the
    // jump's mean: a review's strip, 10 mm off at 0.5 m, had its first peak force 2.8 % high
    // (by the torsion modes' slow 1/N tail) and its torsion shear 6.0e4 against 2.35e7 Pa.
    // Its own modes (the [structure] it is) take the rigid-body motions out by inertia relief
    // and carry both: the default there.
    let free_off_centre = offset != 0.0 && beam.support == SupportName::FreeFree;
    // The analytic modes' own keys (a count, a beam theory) keep them, as the basis named does.
    let analytic = s.modal_basis == Some(ModalBasisName::Analytic)
        || (s.modal_basis.is_none() && (s.modes.is_some() || s.beam_theory.is_some()));
    if free_off_centre && analytic && method != MethodName::Fe {
        warnings.push("the uniform beam's analytic modes (solver.modal_basis = \"analytic\", or solver.modes or beam_theory given) on a free-free beam struck off its centreline: they carry no residual flexibility on a free body, and the torque's jump at the struck section leaves the twist rate's series at its mean there (a review's strip, 10 mm off at 0.5 m: the first peak force 2.8 % high, the torsion shear 6.0e4 against 2.35e7 Pa); leave solver.modal_basis, modes and beam_theory out (the beam's own modes, the default here) or run solver.method = \"fe\"".into());
    }
    let own = !attachments.is_empty() || (free_off_centre && !analytic && s.modal_basis.is_none());
    let use_fe = match method {
        MethodName::Modal
            if s.modal_basis == Some(ModalBasisName::Analytic) && !attachments.is_empty() =>
        {
            return Err(ImpactError::Inconsistent("solver.modal_basis = \"analytic\" with [[beam.mass]] or [[beam.spring]]: the analytic modes are the uniform beam's; the beam's own modes are \"fe\" (its finite elements), or leave solver.modal_basis out".into()));
        }
        MethodName::Modal if own || s.modal_basis == Some(ModalBasisName::Fe) => {
            reasons.push(if attachments.is_empty() && s.modal_basis.is_none() {
                FREE_OFF_CENTRE_BASIS.into()
            } else if attachments.is_empty() {
                "modes from the beam's finite elements (solver.modal_basis = \"fe\", as asked): the [structure] the beam is (one member, a node at the impact point), its own 3D modes instead of the uniform beam's analytic ones".into()
            } else if s.modal_basis.is_some() {
                "modes from the beam's finite elements (solver.modal_basis = \"fe\", as asked): it carries point masses or springs; the [structure] it is (one member, a node at each attachment and at the impact point)".into()
            } else {
                "modes from the beam's finite elements (solver.modal_basis = \"fe\", the default here): it carries point masses or springs, which the uniform beam's analytic modes do not hold; the [structure] it is (one member, a node at each attachment and at the impact point)".into()
            });
            let mut plan = own_modes(scene, beam, position, pulse, (reasons, warnings))?;
            plan.damping = damping;
            return Ok(Method::Modal(plan));
        }
        MethodName::Auto if own && !large && !fe_keys(s) => {
            // As a uniform beam's: the modal method where small-deflection theory holds, on the
            // beam's own modes; the fe method where those cannot carry it (say why).
            let kept = (reasons.len(), warnings.len());
            // The deflection bound again with the carried beam's own static flexibility (its
            // springs may hold less than the uniform beam's supports: a free-free beam on
            // springs has none of its own).
            let own = own_modes(scene, beam, position, pulse, (reasons, warnings)).and_then(|plan| {
                let f = plan.static_flexibility().unwrap_or(0.0);
                let deflection = (pulse.ball_mass * pulse.speed * pulse.speed * f).sqrt();
                if deflection > LARGE_DEFLECTION * length {
                    Err(ImpactError::Inconsistent(format!("the ball's energy could bend it {deflection:.3e} m at the impact point, more than {:.0} % of its length (sqrt(m V^2 / k), k its own static stiffness there): small-deflection theory does not hold", 100.0 * LARGE_DEFLECTION)))
                } else {
                    Ok((plan, deflection))
                }
            });
            match own {
                Ok((mut plan, deflection)) => {
                    reasons.insert(kept.0, if attachments.is_empty() {
                        format!("method modal (auto): Goldsmith's modal series, exact between steps; {FREE_BODY}; {FREE_OFF_CENTRE_BASIS}")
                    } else {
                        format!("method modal (auto): Goldsmith's modal series, exact between steps, on the beam's own modes, which hold its point masses and springs (its 3D finite elements': the [structure] it is, a node at each attachment and at the impact point); the ball's energy bends it at most {deflection:.3e} m (sqrt(m V^2 / k), k its own static stiffness), small against its length (on the paper's beam with a 20 g sensor and a 2000 N/m spring, centred, over 1 ms: 0.067 s against 0.125 s by the fe method; validation/REFERENCES.md 1.13)")
                    });
                    plan.damping = damping;
                    return Ok(Method::Modal(plan));
                }
                Err(why) => {
                    reasons.truncate(kept.0);
                    warnings.truncate(kept.1);
                    let what = if attachments.is_empty() {
                        "a free-free beam struck off its centreline takes its own modes"
                    } else {
                        "the beam carries point masses or springs"
                    };
                    reasons.push(format!("method fe (auto): {what}, and its own modes cannot carry the modal method here: {why}"));
                    true
                }
            }
        }
        MethodName::Fe => {
            reasons
                .push("method fe, as asked: geometrically exact Simo beam with HHT-alpha".into());
            true
        }
        MethodName::Modal => {
            reasons.push(format!(
                "the uniform beam's analytic modes (solver.modal_basis = \"analytic\"{})",
                if s.modal_basis.is_some() {
                    ", as asked"
                } else {
                    ", the default for a [beam] without masses or springs: exact shapes, no mesh"
                }
            ));
            false
        }
        MethodName::Auto if modal::too_many_modes(&m, pulse.duration)? => {
            reasons.push(format!("method fe (auto): the estimated contact duration {:.3e} s excites more of the beam's modes than the modal method's {} below omega t_c = {MODE_CUTOFF}", pulse.duration, modal::MAX_MODES));
            true
        }
        MethodName::Auto if large || fe_keys(s) => {
            reasons.push(format!(
                "method fe (auto): {}",
                if large {
                    format!("the ball's energy could bend the beam {deflection:.3e} m at the impact point, more than {:.0} % of its length (sqrt(m V^2 / k)): small-deflection theory does not hold", 100.0 * LARGE_DEFLECTION)
                } else {
                    "solver.elements, element_size, alpha or time_step given".into()
                }
            ));
            true
        }
        MethodName::Auto => {
            reasons.push(if flexibility > 0.0 {
                format!("method modal (auto): Goldsmith's modal series, exact between steps; the ball's energy bends the beam at most {deflection:.3e} m (sqrt(m V^2 / k)), small against its length")
            } else {
                format!("method modal (auto): Goldsmith's modal series, exact between steps; {FREE_BODY}")
            });
            false
        }
    };
    if use_fe && s.plain_stress_series.is_some() {
        return Err(ImpactError::Inconsistent(
            "solver.plain_stress_series belongs to the modal method; the fe method recovers the stress from its elements".into(),
        ));
    }
    if use_fe && s.residual_flexibility.is_some() {
        return Err(ImpactError::Inconsistent(
            "solver.residual_flexibility belongs to the modal method; the fe method models the whole beam".into(),
        ));
    }
    if use_fe && s.beam_theory.is_some() {
        return Err(ImpactError::Inconsistent(
            "solver.beam_theory belongs to the modal method; the fe beam always has shear and rotary inertia".into(),
        ));
    }
    if use_fe {
        let mut fe =
            fe::plan(beam, s, m, position, damping, attachments, pulse, (reasons, warnings))?;
        // A beam without attachments has the modal method's analytic torsion modes.
        let uniform = fe.attachments.is_empty();
        let speed = torsion.as_ref().map(::modal::Torsion::wave_speed);
        if fe::model(&mut fe, s.fe_model, offset, torsion, reasons)? {
            fe.structure = Some(Box::new(structure::of_beam(&fe, scene, pulse)?));
        }
        if let Some(speed) = speed {
            // The longest element the torsion fronts cross within the window.
            let within = fe::reach(s, speed);
            let h = fe
                .nodes
                .windows(2)
                .filter(|w| (w[0] - position).abs().min((w[1] - position).abs()) <= within)
                .map(|w| w[1] - w[0])
                .fold(0.0, f64::max);
            let advice = |h: f64| {
                if uniform {
                    format!("solver.element_size = {h:.3e} m, or the modal method (the uniform beam's analytic torsion modes do not disperse)")
                } else {
                    format!("solver.element_size = {h:.3e} m")
                }
            };
            fe::torsion_mesh(
                ("the 3D beam", &advice),
                (h, speed, pulse.duration),
                s,
                (reasons, warnings),
            );
        }
        Ok(Method::Fe(fe))
    } else {
        let (chosen, twin) = theory::choose(s.beam_theory, beam, both, pulse, reasons);
        let local =
            modal::local_frequency(&chosen, (pulse.ball_mass, pulse.speed, pulse.max_approach));
        let mut plan = modal::plan(s, chosen, position, damping, (pulse.duration, local), reasons)?;
        plan.twin = twin;
        if let Some(t) = torsion {
            reasons.push(format!(
                "struck {offset} m off the centreline: Saint-Venant torsion modes beside the bending ones (G J = {:.4e} N m^2, rho Ip = {:.4e} kg m, wave speed {:.4e} m/s; warping free), up to the highest bending mode's frequency; the face moves by w + offset x twist",
                t.rigidity(),
                t.rotary_inertia(),
                t.wave_speed()
            ));
            plan.torsion = Some((t, offset));
            // The torsion modes' static share at the site falls as 1/N (the bending modes' as
            // 1/N^3, validation/REFERENCES.md 1.9): truncated, the struck face is too stiff.
            if s.residual_flexibility.is_none()
                && !plan.residual_flexibility
                && plan.static_flexibility().is_some()
            {
                plan.residual_flexibility = true;
                reasons.push("residual flexibility (the default off the centreline): the truncated modes' static compliance at the struck face in series with the contact, and the strains' quasi-static share (mode-acceleration method); the torsion modes' static share falls only as 1/N, so without it the face is too stiff (a 0.5 m cantilever struck 10 mm off the centre line of its 25 mm width, 52 modes: the first contact 1.8 % short and its peak force 2.0 % high; with it within 0.1 % of the converged run); solver.residual_flexibility = false leaves it out".into());
            }
        }
        // A free body's analytic modes have no static flexibility to take the truncated
        // modes' share by (solver.residual_flexibility is refused there), and its first
        // contact is as high as a supported beam's without it; unquantified here, so said
        // with the measured size (a second review's).
        if beam.support == SupportName::FreeFree && plan.static_flexibility().is_none() {
            warnings.push(format!("a free-free beam's analytic modes carry no residual flexibility (a free body has no static flexibility to take it by): the truncated modes' static compliance at the impact point is left out of the contact, whose first peak force then comes out high by their share, as a supported beam's does without it (here {} modes; the paper's strip struck at mid-span at its default 107: 0.73 % above its own modes' 1234.14 N, a review's); solver.modal_basis = \"fe\" takes the beam's own modes, which carry it by inertia relief", plan.modes));
        }
        Ok(Method::Modal(plan))
    }
}

/// Warns when the Hertz contact patch (radius sqrt(R delta) at the largest approach on a
/// rigid support) reaches past a free end of the beam: the contact law is a half-space's, and
/// the beam models put the load at one point, while near a free end the response changes
/// fast with the point (validation/REFERENCES.md 1.6: on the paper's tip, struck 0.1 mm
/// further in, the ball leaves the first contact 3 % slower and the second contact starts 9 %
/// later).
fn free_end(
    beam: &BeamSpec,
    position: f64,
    radius: f64,
    pulse: &Pulse,
    warnings: &mut Vec<String>,
) {
    let free_ends: &[f64] = match beam.support {
        SupportName::ClampedFree => &[beam.length],
        SupportName::FreeFree => &[0.0, beam.length],
        _ => &[],
    };
    let patch = (radius * pulse.max_approach).sqrt();
    if let Some(distance) = free_ends.iter().map(|end| (end - position).abs()).find(|d| *d < patch)
    {
        warnings.push(format!(
            "impact.position is {distance:.3e} m from a free end of the beam, within the contact radius (about {patch:.3e} m): the contact patch runs over the beam's end, where the contact law (a half-space) does not hold, and the beam models load one point where the response changes fast with it (on the paper's tip, struck 0.1 mm further in, the ball leaves the first contact 3 % slower and the second contact starts 9 % later; validation/REFERENCES.md 1.6): strike at least the contact radius inside the end for a result the models vouch for"
        ));
    }
    // A held end: within the section's depth of it the load goes into the support through the
    // depth (Saint-Venant's region), which neither beam model has; closer than the contact
    // radius the patch presses on the support itself. Said with the distance (a review's: 1 mm
    // from the paper's clamp, both methods answered as beams without a word; 1 um out the fe
    // method's elements of half a micrometre read the clamp 24 % low).
    let held: Vec<f64> = match beam.support {
        SupportName::ClampedFree => vec![0.0],
        SupportName::FreeFree => vec![],
        _ => vec![0.0, beam.length],
    };
    let depth = beam.thickness;
    if let Some((end, distance)) = held
        .iter()
        .map(|end| (*end, (end - position).abs()))
        .find(|(_, d)| *d > 0.0 && *d < depth.max(patch))
    {
        let patch_words = if distance < patch {
            format!(", and within the contact radius (about {patch:.3e} m): the contact patch presses on the support itself, where the contact law (a half-space) does not hold")
        } else {
            String::new()
        };
        warnings.push(format!(
            "impact.position is {distance:.3e} m from the supported end at x = {end} m, closer than the beam's thickness {depth:.3e} m{patch_words}: there the load goes into the support through the section's depth, which beam theory (both methods) does not model; the displacement under the ball and the support's stress are a beam's answer (the two methods agree on it within about 1 % down to 1 mm on the paper's strip, validation/REFERENCES.md 1.5), not the solid's"
        ));
    }
}

/// A point mass's `rotary_inertia` (`key` the mass's, e.g. `beam.mass[0]`) about its
/// section's axes E1, E2, E3 (kg m^2), each checked.
///
/// # Errors
/// `InvalidField` naming the component that is negative or not finite.
pub(crate) fn rotary_inertia(
    key: &str,
    given: Option<crate::scene::RotaryInertia>,
) -> Result<[f64; 3], ImpactError> {
    let axes = given.map_or([0.0; 3], crate::scene::RotaryInertia::axes);
    for (i, value) in axes.iter().enumerate() {
        let name = match given {
            Some(crate::scene::RotaryInertia::Axes(_)) => format!("{key}.rotary_inertia[{i}]"),
            _ => format!("{key}.rotary_inertia"),
        };
        not_negative(&name, *value, "kg m^2")?;
    }
    Ok(axes)
}

/// The beam's `[[beam.mass]]` and `[[beam.spring]]`, checked (on the beam, not negative),
/// in order along it. Warns of a mass where the ball strikes (it has no face in the model) and
/// says which of a mass's rotary inertias act on the planar beam (about the width axis only).
fn attachments(
    beam: &BeamSpec,
    position: f64,
    radius: f64,
    pulse: &Pulse,
    (reasons, warnings): (&mut Vec<String>, &mut Vec<String>),
) -> Result<Vec<Attachment>, ImpactError> {
    let length = beam.length;
    let place = |key: String, at: f64| -> Result<f64, ImpactError> {
        if at.is_finite() && (0.0..=length).contains(&at) {
            Ok(at)
        } else {
            Err(invalid(
                &key,
                at,
                &format!("must be on the beam, 0 <= at <= beam.length = {length} (m)"),
            ))
        }
    };
    let mut out = Vec::new();
    let patch = (radius * pulse.max_approach).sqrt();
    for (k, m) in beam.masses.iter().enumerate() {
        let at = place(format!("beam.mass[{k}].at"), m.at)?;
        let mass = not_negative(&format!("beam.mass[{k}].mass"), m.mass, "kg")?;
        let rotary = rotary_inertia(&format!("beam.mass[{k}]"), m.rotary_inertia)?;
        if rotary[0] > 0.0 || rotary[2] > 0.0 {
            reasons.push(format!("beam.mass[{k}].rotary_inertia: about the beam's axis ({} kg m^2, the twist) and the thickness axis ({} kg m^2, bending in the width's plane) it acts on the 3D beam (an off-centre strike), not on a planar one; about the width axis ({} kg m^2) on both", rotary[0], rotary[2], rotary[1]));
        }
        if (at - position).abs() <= patch {
            warnings.push(format!("beam.mass[{k}] at x = {at} m sits where the ball strikes (within the contact radius {patch:.3e} m): the mass has no face in the model, the ball meets the beam's face and the mass only adds its inertia at that node"));
        }
        out.push(Attachment {
            at,
            mass,
            rotary_inertia: rotary,
            stiffness: 0.0,
            rotational_stiffness: 0.0,
        });
    }
    for (k, sp) in beam.springs.iter().enumerate() {
        let at = place(format!("beam.spring[{k}].at"), sp.at)?;
        let stiffness = not_negative(&format!("beam.spring[{k}].stiffness"), sp.stiffness, "N/m")?;
        let rotational_stiffness = not_negative(
            &format!("beam.spring[{k}].rotational_stiffness"),
            sp.rotational_stiffness.unwrap_or(0.0),
            "N m/rad",
        )?;
        out.push(Attachment {
            at,
            mass: 0.0,
            rotary_inertia: [0.0; 3],
            stiffness,
            rotational_stiffness,
        });
    }
    out.sort_by(|a, b| a.at.total_cmp(&b.at));
    Ok(out)
}

/// `impact.offset` (m), checked: on the face (at most half its size across, `width`: the
/// section's width on a thickness face, its thickness on a width face, from the centreline).
/// Warns when the contact patch (radius sqrt(R delta) at the largest approach on a rigid
/// support) reaches past the face's edge, where the contact law (a half-space) does not hold,
/// or comes within its own radius of it.
fn offset(
    width: f64,
    offset: Option<f64>,
    radius: f64,
    pulse: &Pulse,
    warnings: &mut Vec<String>,
) -> Result<f64, ImpactError> {
    let Some(e) = offset else { return Ok(0.0) };
    let half = 0.5 * width;
    if !(e.is_finite() && e.abs() <= half) {
        return Err(invalid(
            "impact.offset",
            e,
            &format!("must be on the struck face, at most half its size across ({width} m) from the centreline: -{half} <= offset <= {half} (m)"),
        ));
    }
    let patch = (radius * pulse.max_approach).sqrt();
    if e.abs() + patch > half {
        warnings.push(format!(
            "impact.offset = {e} m puts the contact patch (radius about {patch:.3e} m) past the face's edge ({:.3} of the face's half-size {half} m): the contact law (a half-space) does not hold there, and the beam models load the point as if the face went on",
            (e.abs() + patch) / half
        ));
    } else if e.abs() + 2.0 * patch > half {
        // Within its own radius of the edge: a review's patch at 0.99 of the half-size had
        // been passed without a word while the docs promised a warning near the edge.
        warnings.push(format!(
            "impact.offset = {e} m brings the contact patch (radius about {patch:.3e} m) within its own radius of the face's edge (its rim at {:.3} of the face's half-size {half} m): the contact law takes the face for a half-space, and the edge's free surface there makes the contact more compliant than it says (by how much is not measured here); strike at least two patch radii inside the edge for a result the law vouches for",
            (e.abs() + patch) / half
        ));
    }
    Ok(e)
}

/// The contact step (s) and the modal method's energy tolerance, with the reason.
fn contact_step(
    method: &Method,
    s: &SolverSpec,
    pulse: &Pulse,
    reasons: &mut Vec<String>,
) -> Result<(f64, Option<f64>), ImpactError> {
    let estimated_duration = pulse.duration;
    let samples = match method {
        Method::Fe(fe) => fe.samples_per_pulse,
        _ => s.samples_per_pulse.unwrap_or(match s.adaptive_step {
            Some(false) => DEFAULT_SAMPLES_PER_PULSE,
            _ => DEFAULT_ADAPTIVE_SAMPLES_PER_PULSE,
        }),
    };
    if !(10..=MAX_SAMPLES_PER_PULSE).contains(&samples) {
        return Err(invalid(
            "solver.samples_per_pulse",
            samples,
            "must be at least 10 and at most 1000000",
        ));
    }
    let time_step = estimated_duration / samples as f64;
    let is_fe = matches!(method, Method::Fe(_));
    let energy_tolerance = match (is_fe, s.adaptive_step, s.energy_tolerance) {
        (true, None, None) => None,
        (true, ..) => {
            return Err(ImpactError::Inconsistent(
                "solver.adaptive_step and energy_tolerance belong to the modal method; the fe method adapts its step on the ball's local error".into(),
            ))
        }
        (_, Some(false), Some(_)) => {
            return Err(ImpactError::Inconsistent(
                "solver.energy_tolerance is the adaptive step's: it has no use with adaptive_step = false".into(),
            ))
        }
        (_, Some(false), None) => None,
        (_, _, tol) => {
            let tol = tol.unwrap_or(DEFAULT_ENERGY_TOLERANCE);
            if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                return Err(invalid(
                    "solver.energy_tolerance",
                    tol,
                    "must be a fraction of the impact energy, 0 < tolerance < 1",
                ));
            }
            Some(tol)
        }
    };
    reasons.push(match (is_fe, energy_tolerance) {
        (true, _) => format!(
            "time step {time_step:.4e} s in contact: {samples} steps per estimated contact duration {estimated_duration:.4e} s ({})", pulse.source()
        ),
        (_, Some(tol)) => format!(
            "adaptive step in contact, at most {time_step:.4e} s ({samples} per estimated contact duration {estimated_duration:.4e} s, {}), halved down to 1/{} of it to keep the energy mismatch within {tol:.1e} of the impact energy per contact duration",
            pulse.source(),
            1usize << FINEST_LEVEL
        ),
        (_, None) => format!(
            "uniform time step {time_step:.4e} s in contact: {samples} steps per estimated contact duration {estimated_duration:.4e} s ({})", pulse.source()
        ),
    });
    Ok((time_step, energy_tolerance))
}

/// The first elastic mode's period (s) of the plan's beam.
fn first_period(method: &Method) -> Option<f64> {
    let beam = match method {
        Method::Modal(m) => match &m.basis {
            ModalBasis::Analytic(beam) => beam,
            ModalBasis::Fe(fe) => return fe.fe.first_period(),
        },
        Method::Fe(fe) => return fe.first_period(),
        Method::HalfSpace => return None,
    };
    let omega = beam.modes(3).ok()?.into_iter().map(|m| m.omega).find(|w| *w > 0.0)?;
    Some(2.0 * PI / omega)
}

/// A value allowed but far from any ball or beam, most likely typed in another unit.
fn slip(warnings: &mut Vec<String>, field: &str, value: f64, why: &str, meant: f64) {
    warnings.push(format!(
        "{field} = {}: {why}; if so, the value meant is {} (the scene file is in SI units)",
        show(value),
        show(meant)
    ));
}

/// Solids are denser than 100 kg/m^3 (cork is 120, balsa 150).
fn density_slip(warnings: &mut Vec<String>, field: &str, rho: f64) {
    if rho < 100.0 {
        slip(warnings, field, rho, "lighter than any solid, as if typed in g/cm^3", rho * 1e3);
    }
}

/// Soft rubber is about 1e6 Pa: a smaller modulus was most likely typed in MPa (or GPa).
fn modulus_slip(warnings: &mut Vec<String>, field: &str, e: f64) {
    if e < 1e3 {
        slip(warnings, field, e, "softer than rubber, as if typed in GPa", e * 1e9);
    } else if e < 1e6 {
        slip(warnings, field, e, "softer than rubber, as if typed in MPa", e * 1e6);
    }
}

/// Metals and polymers yield above 1e6 Pa.
fn yield_slip(warnings: &mut Vec<String>, field: &str, y: Option<f64>) {
    if let Some(y) = y.filter(|y| *y < 1e6) {
        let why = "below any metal's or polymer's yield stress, as if typed in MPa";
        slip(warnings, field, y, why, y * 1e6);
    }
}

/// Warnings for values that are allowed but most likely typed in another unit, or sizes that
/// make no beam, each naming the field and the value probably meant.
fn unit_slips(scene: &Scene, warnings: &mut Vec<String>) {
    let b = &scene.ball;
    density_slip(warnings, "ball.density", b.density);
    modulus_slip(warnings, "ball.youngs_modulus", b.youngs_modulus);
    yield_slip(warnings, "ball.yield_stress", b.yield_stress);
    if b.radius > 1.0 {
        let why = "a ball over a metre in radius, as if typed in mm";
        slip(warnings, "ball.radius", b.radius, why, b.radius * 1e-3);
    }
    if let Some(beam) = &scene.beam {
        density_slip(warnings, "beam.density", beam.density);
        modulus_slip(warnings, "beam.youngs_modulus", beam.youngs_modulus);
        yield_slip(warnings, "beam.yield_stress", beam.yield_stress);
        if b.radius > beam.length {
            warnings.push(format!(
                "ball.radius = {} m is larger than beam.length = {} m: check both, in metres",
                show(b.radius),
                show(beam.length)
            ));
        }
    }
    if let Some(st) = &scene.structure {
        // The structure's section and each segment's own (a stepped member), as a beam's.
        let own = st.segments.iter().enumerate().filter_map(|(k, seg)| {
            seg.section.as_ref().map(|sec| (format!("structure.segment[{k}].section"), sec))
        });
        for (key, sec) in std::iter::once(("structure.section".to_string(), &st.section)).chain(own)
        {
            if let Some(rho) = sec.density {
                density_slip(warnings, &format!("{key}.density"), rho);
            }
            if let Some(e) = sec.youngs_modulus {
                modulus_slip(warnings, &format!("{key}.youngs_modulus"), e);
            }
            for (field, size) in [("width", sec.width), ("thickness", sec.thickness)] {
                if let Some(size) = size.filter(|s| *s > 1.0) {
                    let why = "a section over a metre across, as if typed in mm";
                    slip(warnings, &format!("{key}.{field}"), size, why, size * 1e-3);
                }
            }
        }
        yield_slip(warnings, "structure.yield_stress", st.yield_stress);
    }
    if let Some(h) = &scene.half_space {
        modulus_slip(warnings, "half_space.youngs_modulus", h.youngs_modulus);
        yield_slip(warnings, "half_space.yield_stress", h.yield_stress);
    }
}

impl Plan {
    /// Validates `scene` and makes every choice: the model, the modes or the mesh, the step,
    /// the law.
    ///
    /// # Errors
    /// `InvalidField` naming the first field with a bad value, `Inconsistent` for a combination
    /// that is not a scene (both or neither of speed and drop height, a plastic law without a
    /// yield stress, ...).
    pub fn new(scene: &Scene) -> Result<Self, ImpactError> {
        let mut reasons = Vec::new();
        let mut warnings = Vec::new();
        let (ball_material, radius, ball_mass) = ball(&scene.ball, &mut warnings)?;
        let speed = impact_speed(&scene.impact)?;
        let gravity = if scene.impact.gravity { GRAVITY } else { 0.0 };
        let (counterface, struck) = struck_body(scene)?;
        let hertz =
            Hertz::between(&ball_material, &counterface, hertz::geometry::sphere_on_flat(radius)?)?;
        let rigid = HalfSpaceImpact::elastic(&hertz, ball_mass, speed)?;
        let estimated_duration = rigid.duration;
        let yield_stress = hertz::softer_yield_stress(&ball_material, &counterface);
        let law = Law::resolve(
            &scene.contact,
            &LawContext { hertz, ball_mass, speed, yield_stress },
            &mut reasons,
            &mut warnings,
        )?;

        let s = &scene.solver;
        check_method_keys(s)?;
        // Hunt-Crossley's damping raises the force while the approach is small, so its pulse
        // peaks before Hertz's half duration: the modes and meshes are sized for a pulse
        // rising that fast (at e = 0.02 on the paper's tip the modes sized for Hertz's 41 us
        // gave a first peak 29 % high, a review's).
        let mut duration = estimated_duration;
        // The contact's own length on a rigid support, for the half-space's default window: a
        // damped one creeps out long after Hertz's duration (at e = 0.02 a review's default
        // window ended before it, and the restitution went unreported).
        let mut lasts = estimated_duration;
        if let Law::HuntCrossley(hc) = &law {
            lasts = hc.half_space_duration(ball_mass, speed)?.max(estimated_duration);
            let rise = hc.half_space_peak_time(ball_mass, speed)?;
            if 2.0 * rise < 0.9 * estimated_duration {
                duration = 2.0 * rise;
                reasons.push(format!("Hunt-Crossley damping (chi V = {:.3}) brings the peak force forward to {:.4e} s on a rigid support (Hertz's half duration {:.4e} s): the modes and meshes are sized for a pulse of {duration:.4e} s", hc.damping_factor() * speed, rise, 0.5 * estimated_duration));
            }
        }
        let damped = duration < estimated_duration;
        let pulse = Pulse { ball_mass, speed, duration, max_approach: rigid.max_approach, damped };
        let method = match struck {
            Struck::HalfSpace
                if scene.impact.offset.is_some()
                    || scene.impact.at.is_some()
                    || scene.impact.direction.is_some() =>
            {
                return Err(ImpactError::Inconsistent(
                    "impact.offset, at and direction belong to a [beam] or a [structure]; a [half_space] has none".into(),
                ))
            }
            Struck::HalfSpace => half_space(s, &mut reasons)?,
            Struck::Beam(beam) => beam_method(scene, beam, &pulse, &mut reasons, &mut warnings)?,
            Struck::Structure(_) if s.modal_basis == Some(ModalBasisName::Analytic) => {
                return Err(ImpactError::Inconsistent("solver.modal_basis = \"analytic\" with a [structure]: the analytic modes are a uniform [beam]'s; a structure's modes are \"fe\" (its own finite elements), the default".into()));
            }
            Struck::Structure(st)
                if modal_basis_implies_modal(s, &mut reasons) == MethodName::Modal =>
            {
                if s.method == MethodName::Modal {
                    reasons.push("method modal, as asked".into());
                }
                Method::Modal(structure::modal_plan(
                    scene,
                    st,
                    &pulse,
                    (&mut reasons, &mut warnings),
                )?)
            }
            Struck::Structure(st) => {
                if s.method == MethodName::Auto {
                    reasons.push("method fe (auto): a [structure] runs by the fe method's 3D beam, which follows it without a modal model; solver.method = \"modal\" takes its own modes (their eigen-solution first)".into());
                }
                Method::Fe(structure::plan(scene, st, &pulse, (&mut reasons, &mut warnings))?)
            }
        };
        // The contact step from the pulse the modes and meshes are sized for (a damped
        // contact's shorter one: from Hertz's the fe method's contact step had come out longer
        // than its free-flight step, a review's crash).
        let (time_step, energy_tolerance) = contact_step(&method, s, &pulse, &mut reasons)?;
        unit_slips(scene, &mut warnings);

        let default_end = match method {
            Method::HalfSpace => 4.0 * lasts,
            Method::Modal(_) | Method::Fe(_) => DEFAULT_END_TIME,
        };
        let end_time = match s.end_time {
            Some(t) => bounded("solver.end_time", t, range::TIME, "s")?,
            None => {
                reasons.push(format!("end time {default_end:.4e} s (default)"));
                default_end
            }
        };
        if let Method::Fe(fe) = &method {
            long_run(fe, end_time, estimated_duration, &mut warnings);
        }
        let output_interval = match s.output_interval {
            Some(dt) => positive("solver.output_interval", dt, "s")?,
            None => end_time / DEFAULT_OUTPUTS,
        };
        let rows = end_time / output_interval;
        if rows > MAX_HISTORY_ROWS {
            return Err(invalid(
                "solver.output_interval",
                show(output_interval),
                &format!(
                    "must be at least solver.end_time / {MAX_HISTORY_ROWS:e} = {:e} s: the history would hold {rows:.1e} rows ({:.1e} bytes)",
                    end_time / MAX_HISTORY_ROWS,
                    rows * HISTORY_ROW_BYTES
                ),
            ));
        }

        let (modes, elements, beam_theory) = match &method {
            Method::Modal(m) => match &m.basis {
                ModalBasis::Analytic(beam) => (m.modes, 0, Some(theory::name(beam))),
                ModalBasis::Fe(basis) => (0, basis.elements(), None),
            },
            Method::Fe(fe) => (0, fe.elements(), None),
            Method::HalfSpace => (0, 0, None),
        };
        let first_period = first_period(&method);
        Ok(Self {
            name: scene.name.clone(),
            summary: PlanSummary {
                method: method.kind(),
                modes,
                elements,
                time_step,
                contact_law: law.name(),
                beam_theory,
                structure: matches!(struck, Struck::Structure(_)),
                reasons,
            },
            method,
            law,
            ball_mass,
            ball_radius: radius,
            speed,
            gravity,
            end_time,
            time_step,
            energy_tolerance,
            output_interval,
            estimated_duration,
            thickness: match struck {
                Struck::Beam(b) => Some(b.thickness),
                Struck::Structure(st) => st.section.thickness,
                Struck::HalfSpace => None,
            },
            width: match struck {
                Struck::Beam(b) => Some(b.width),
                Struck::Structure(st) => st.section.width,
                Struck::HalfSpace => None,
            },
            poisson_ratios: [ball_material.poisson_ratio, counterface.poisson_ratio],
            beam_yield_stress: match struck {
                Struck::Beam(b) => b.yield_stress,
                Struck::Structure(st) => st.yield_stress,
                Struck::HalfSpace => None,
            },
            field: false,
            first_period,
            warnings,
        })
    }

    /// Scene name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// How the struck body is modelled.
    pub fn method(&self) -> &Method {
        &self.method
    }

    /// The contact law with its parameters.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// Ball mass (kg).
    pub fn ball_mass(&self) -> f64 {
        self.ball_mass
    }

    /// Impact speed (m/s).
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Simulated time from first touch (s).
    pub fn end_time(&self) -> f64 {
        self.end_time
    }

    /// Estimated duration of the first contact on a rigid support (s).
    pub fn estimated_duration(&self) -> f64 {
        self.estimated_duration
    }

    /// What was chosen and why, as the report gives it.
    pub fn summary(&self) -> &PlanSummary {
        &self.summary
    }

    /// Whether the run can record a field along its beam: not on a half-space (no beam).
    pub fn can_record_field(&self) -> bool {
        !matches!(self.method, Method::HalfSpace)
    }

    /// The plan, its run recording the beam's field ([`crate::Field`]: displacement, slope,
    /// moment and stress at [`FIELD_POINTS`] points along the beam, at every recorded instant).
    ///
    /// # Errors
    /// `Inconsistent` where [`Plan::can_record_field`] is false, `InvalidField` naming
    /// `solver.output_interval` when the field would hold more than [`MAX_FIELD_VALUES`]
    /// values (its size is said).
    pub fn with_field(mut self) -> Result<Self, ImpactError> {
        if matches!(self.method, Method::HalfSpace) {
            return Err(ImpactError::Inconsistent(
                "a [half_space] has no beam: no field along it to write".into(),
            ));
        }
        // The free flight's instants plus about 200 a contact of the estimated duration,
        // counted as if the whole window were contact at worst a tenth of it.
        let instants = self.end_time / self.output_interval
            + 0.1 * self.end_time / (self.estimated_duration / 200.0);
        // The modal field's points: the ends of FIELD_POINTS intervals and the impact point;
        // the fe field's: its nodes, the elements' midpoints and the impact point (those of
        // the plan's mesh: a tolerance's finer meshes more).
        let points = match &self.method {
            Method::Fe(fe) => 2 * fe.nodes.len(),
            _ => FIELD_POINTS + 2,
        };
        let values = instants * points as f64 * 4.0;
        if values > MAX_FIELD_VALUES {
            return Err(invalid(
                "solver.output_interval",
                show(self.output_interval),
                &format!(
                    "too fine for a field: {instants:.2e} instants x {points} points x 4 quantities = {values:.2e} values ({:.1e} bytes), above {MAX_FIELD_VALUES:e}; a larger output interval or a shorter solver.end_time",
                    values * 8.0
                ),
            ));
        }
        self.field = true;
        Ok(self)
    }

    /// Warnings about the scene (accepted, but worth a look).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The warning that the run will take more than [`LONG_RUN_STEPS`] steps, if it will: a
    /// front end says it before the run, not only in the report after it.
    pub fn long_run(&self) -> Option<&str> {
        self.warnings.iter().find(|w| w.starts_with(LONG_RUN)).map(String::as_str)
    }
}
