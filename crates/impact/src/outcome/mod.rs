//! What a run produces: the [`Report`] (per-contact metrics, the energy ledger, the largest
//! displacement, the equivalent static force) and the [`History`] (time series).

mod field;
mod history;
mod stress;

pub use field::Field;
pub use history::{History, Sample};
pub(crate) use stress::Envelope;
pub use stress::{BendingStress, SupportStress};

use crate::plan::{Plan, PlanSummary};
use serde::{Deserialize, Serialize};

/// The fraction of a contact's peak force that bounds its pulse (`Contact::pulse_duration`).
pub const PULSE_FRACTION: f64 = 0.05;

/// A contact is significant when its peak force is at least this fraction of its run's first
/// contact's peak: the one threshold of every comparison of two runs ([`Report::differences_from`]),
/// and so of `solver.tolerance`, `accuracy`, `compare` and the warning about later contacts.
/// The paper's tip has a third contact at 8.6e-3 of the first's peak that a user reads, and
/// grazes of 1e-4 whose count changes with the resolution.
pub const SIGNIFICANT_PEAK: f64 = 1e-3;

/// What a run produces.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Per-contact metrics and the energy ledger.
    pub report: Report,
    /// Time series.
    pub history: History,
    /// The beam along its length at each recorded instant, when the plan asked for it
    /// ([`Plan::with_field`]).
    pub field: Option<Field>,
}

/// One contact between the ball and the beam.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Onset time (s), located by root finding on the approach.
    pub start: f64,
    /// Duration (s), to the located separation (or to the end of the run if still in contact).
    pub duration: f64,
    /// False if the run ended during this contact.
    pub complete: bool,
    /// Pulse duration (s): from the force's first rise through [`PULSE_FRACTION`] of its peak
    /// to its first fall back through it after the peak, as an instrumented experiment reads a
    /// force pulse. Shorter than `duration` where the ball then rides on lightly (in its print,
    /// or on a beam that carries it), and defined even when the run ends during the contact.
    pub pulse_duration: f64,
    /// Largest contact force (N).
    pub peak_force: f64,
    /// Largest approach (m).
    pub max_approach: f64,
    /// Impulse, integral of F dt (N s).
    pub impulse: f64,
    /// Ball velocity toward the beam at onset (m/s).
    pub ball_velocity_before: f64,
    /// Ball velocity toward the beam at separation (m/s); negative when it rebounds.
    pub ball_velocity_after: f64,
    /// Rim radius of the permanent print after this contact (m); 0 if elastic so far.
    pub print_radius: f64,
    /// Central contact pressure p0 at the peak force (Pa): Hertz's, or for a Thornton contact
    /// that loaded past first yield the pressure its law caps (a later one reloading the print
    /// elastically: Hertz's on the print's enlarged radius R_p, Thornton 1997).
    pub max_pressure: f64,
    /// Contact radius a at the peak force (Pa's circle, m).
    pub contact_radius: f64,
    /// The largest shear stress below the surface in the ball (Pa), on the contact's axis
    /// (Johnson eq. 3.45 with the ball's Poisson ratio; about 0.31 p0 for nu = 0.3), and
    /// its depth below the surface (m, about 0.48 a). For a Thornton contact loading past
    /// yield it is Hertz's at p0 = p_y: the plastic zone beneath is not modelled.
    pub ball_max_shear: f64,
    /// Its depth (m).
    pub ball_max_shear_depth: f64,
    /// The same in the struck body (beam or half-space), with its Poisson ratio (Pa).
    pub body_max_shear: f64,
    /// Its depth (m).
    pub body_max_shear_depth: f64,
    /// Steps taken in contact.
    pub steps: usize,
}

/// Where the energy is at the end of the run (J). Each term is computed from the state it
/// describes; `balance_error` is what is left over.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// Ball kinetic energy at first touch plus its potential energy there (0).
    pub initial: f64,
    /// Ball kinetic energy, m v^2 / 2.
    pub ball_kinetic: f64,
    /// Ball potential energy relative to first touch, -m g u.
    pub ball_potential: f64,
    /// Beam energy, sum over modes of (v^2 + omega^2 q^2)/2.
    pub beam: f64,
    /// Elastic energy stored in the contact (the law's).
    pub contact_stored: f64,
    /// Plastic and damping work of the contact plus modal damping work.
    pub dissipated: f64,
    /// Energy removed by the time integrator itself: HHT-alpha's damping of the frequencies
    /// above the mesh's resolution, summed step by step from the Newmark energy identity (the
    /// fe method; 0 for the modal method, whose propagation is exact).
    pub numerical_dissipation: f64,
    /// initial - (all the above): what no term accounts for.
    pub balance_error: f64,
}

impl Energy {
    /// The ledger from its terms (J); the balance error is what they leave of the initial
    /// energy, never a term of its own.
    pub(crate) fn new(
        initial: f64,
        ball_kinetic: f64,
        ball_potential: f64,
        beam: f64,
        contact_stored: f64,
        dissipated: f64,
        numerical_dissipation: f64,
    ) -> Self {
        let mut energy = Self {
            initial,
            ball_kinetic,
            // -m g u with g = 0 is -0: written as 0 (+ 0.0 turns -0 into 0, nothing else).
            ball_potential: ball_potential + 0.0,
            beam,
            contact_stored,
            dissipated,
            numerical_dissipation,
            balance_error: 0.0,
        };
        energy.balance_error = initial - energy.held() - numerical_dissipation;
        energy
    }

    /// What the ball, the beam and the contact hold plus what has been dissipated (J): constant
    /// in exact arithmetic.
    pub(crate) fn held(&self) -> f64 {
        self.ball_kinetic + self.ball_potential + self.beam + self.contact_stored + self.dissipated
    }
}

/// Everything a run reports (SI units; ball velocities positive toward the beam). It reads
/// back from its JSON (a study's journal keeps finished runs that way).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Scene name.
    pub name: String,
    /// What was modelled and why.
    pub plan: PlanSummary,
    /// Things the user should look at.
    pub warnings: Vec<String>,
    /// Impact speed (m/s).
    pub impact_speed: f64,
    /// Every contact in order.
    pub contacts: Vec<Contact>,
    /// Number of contacts.
    pub contact_count: usize,
    /// -(velocity after)/(velocity before) of the first contact; null if it did not end.
    pub restitution: Option<f64>,
    /// Largest beam displacement at the impact point over the run (m).
    pub max_displacement: f64,
    /// When it happened (s).
    pub max_displacement_time: f64,
    /// Whether the largest displacement sits at the window's end (it was still growing: a
    /// longer `solver.end_time` would find a larger one; a warning names the window).
    pub max_displacement_at_window_end: bool,
    /// The beam's largest bending stress over the beam and the window; null on a half-space.
    pub bending_stress: Option<BendingStress>,
    /// The struck section's largest rotation about the beam's axis (rad, magnitude) for an
    /// off-centre strike (`impact.offset`) or the fe method's 3D beam; absent from the JSON
    /// otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_twist: Option<f64>,
    /// When it happened (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_twist_time: Option<f64>,
    /// The largest section rotation about its own axis anywhere on the beam or structure,
    /// where and when (the fe method's 3D beam: at its nodes and accepted steps; at a corner,
    /// each member's end section about its own member's axis); absent from the JSON otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub largest_twist: Option<Twist>,
    /// The largest Saint-Venant shear stress of torsion (Pa), at the middle of the section's
    /// long side, k G t theta' (validation/REFERENCES.md 1.9), where (arc length of the
    /// section, m) and when (s): the fe method's 3D beam at the elements' midpoints and accepted
    /// steps; the modal method (off-centre) at the ends that hold the twist and beside the
    /// struck section, searched between instants; absent from the JSON otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torsion_shear: Option<Twist>,
    /// Static stiffness of the beam at the impact point (N/m); null for a half-space or a
    /// free-free beam.
    pub static_stiffness: Option<f64>,
    /// Static stiffness x max displacement (N); null where the stiffness is.
    pub equivalent_static_force: Option<f64>,
    /// Energy ledger at the end of the run.
    pub energy: Energy,
    /// The relative error the run's contacts and largest displacement are expected to carry,
    /// where the run estimated it (`solver.tolerance`: the Richardson estimate from the last
    /// two meshes); null otherwise.
    pub estimated_error: Option<f64>,
    /// What the beam theory leaves out, measured (relative, the worst of the contacts, the
    /// largest displacement and the largest stress): an Euler-Bernoulli run asked for where
    /// shear and rotary inertia matter is run again with Timoshenko modes at the same modes,
    /// and this is their difference, part of `estimated_error`; null otherwise.
    #[serde(default)]
    pub model_error: Option<f64>,
    /// Wall-clock time of the run (s).
    pub wall_time: f64,
}

/// A largest value along the beam: magnitude (rad for a twist, Pa for a stress), where (arc
/// length from the first node, m) and when (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Magnitude (rad, or Pa).
    pub max: f64,
    /// Arc length from the first node (m).
    pub position: f64,
    /// When (s).
    pub time: f64,
}

/// What a solver knows at the end of a run, before the derived fields are filled in.
pub(crate) struct Ending {
    pub(crate) plan: PlanSummary,
    pub(crate) warnings: Vec<String>,
    pub(crate) contacts: Vec<Contact>,
    /// (largest displacement at the impact point (m), when (s)).
    pub(crate) max_displacement: (f64, f64),
    pub(crate) static_stiffness: Option<f64>,
    pub(crate) energy: Energy,
    pub(crate) wall_time: f64,
    /// The bending stress envelope, where the solver recovers it.
    pub(crate) bending_stress: Option<BendingStress>,
    /// The struck section's largest twist (rad) and when (s), for an off-centre strike.
    pub(crate) twist: Option<(f64, f64)>,
    /// The largest twist anywhere, where and when (3D fe).
    pub(crate) largest_twist: Option<Twist>,
    /// The largest Saint-Venant shear stress, where and when (3D fe).
    pub(crate) torsion_shear: Option<Twist>,
    /// The last instant the solver observed (s): a maximum there is not yet one.
    pub(crate) last_time: f64,
}

impl Report {
    /// The report of a run of `plan`: restitution from the first complete contact, the
    /// equivalent static force from the static stiffness.
    pub(crate) fn assemble(plan: &Plan, mut end: Ending) -> Self {
        small_strain_warnings(plan, &end.contacts, &mut end.warnings);
        // The largest subsurface shear per unit pressure and its depth per unit radius depend
        // on the Poisson ratios alone: searched once for every contact (a search is 160
        // arctangents; the paper's 29 contacts had taken 0.2 ms of a 12 ms run).
        // The plan validated both ratios (in (-1, 0.5)): the search answers for each.
        let shear =
            plan.poisson_ratios.map(|nu| hertz::max_subsurface_shear(nu).unwrap_or((0.0, 0.0)));
        for c in &mut end.contacts {
            contact_stresses(plan, shear, c);
        }
        let mut more = Vec::new();
        envelope_warnings(plan, &end, &mut more);
        ledger_warning(&end.energy, &mut more);
        end.warnings.extend(more);
        let at_window_end = displacement_at_window_end(plan, &end);
        let restitution = end
            .contacts
            .first()
            .filter(|c| c.complete)
            .map(|c| -c.ball_velocity_after / c.ball_velocity_before);
        Self {
            name: plan.name.clone(),
            plan: end.plan,
            warnings: end.warnings,
            impact_speed: plan.speed,
            contact_count: end.contacts.len(),
            contacts: end.contacts,
            restitution,
            max_displacement: end.max_displacement.0,
            max_displacement_time: end.max_displacement.1,
            max_displacement_at_window_end: at_window_end,
            static_stiffness: end.static_stiffness,
            equivalent_static_force: end.static_stiffness.map(|k| k * end.max_displacement.0),
            energy: end.energy,
            estimated_error: None,
            model_error: None,
            wall_time: end.wall_time,
            bending_stress: end.bending_stress,
            max_twist: end.twist.map(|t| t.0),
            max_twist_time: end.twist.map(|t| t.1),
            largest_twist: end.largest_twist,
            torsion_shear: end.torsion_shear,
        }
    }
}

/// How far a report is from a reference report, each as a relative error (-): see
/// [`Report::differences_from`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Differences {
    /// The first contact's duration.
    pub first_duration: f64,
    /// The first contact's peak force.
    pub first_peak_force: f64,
    /// The worst over the significant contacts of the start (after the first), the duration
    /// (where both ended within the window) and the peak force, at most 1: a significant
    /// contact that one run has and the other has not counts as 1 (its peak is missed whole),
    /// and so does any error beyond it (the sequence is not resolved: the contacts paired in
    /// order are no longer the same contacts).
    pub contact_sequence: f64,
    /// The largest displacement at the impact point.
    pub max_displacement: f64,
    /// The beam's largest bending stress (`bending_stress.max`); 0 where either run has none
    /// (a half-space).
    pub max_stress: f64,
    /// Whether both runs have the same number of significant contacts.
    pub same_contacts: bool,
}

impl Differences {
    /// The worst of the five.
    pub fn worst(&self) -> f64 {
        self.first_duration
            .max(self.first_peak_force)
            .max(self.contact_sequence)
            .max(self.max_displacement)
            .max(self.max_stress)
    }
}

impl std::fmt::Display for Differences {
    /// Each difference by name, e.g. "first contact 4.8e-4 in duration and 5.6e-4 in peak
    /// force, contact sequence 8.4e-3, largest displacement 2.0e-5, largest stress 1.0e-4".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "first contact {:.1e} in duration and {:.1e} in peak force, ",
            self.first_duration, self.first_peak_force
        )?;
        if self.same_contacts {
            write!(f, "contact sequence {:.1e}", self.contact_sequence)?;
        } else {
            write!(f, "a significant contact in one run only")?;
        }
        write!(
            f,
            ", largest displacement {:.1e}, largest stress {:.1e}",
            self.max_displacement, self.max_stress
        )
    }
}

impl Report {
    /// Relative differences from `reference`. A contact is significant when its peak force is
    /// at least [`SIGNIFICANT_PEAK`] times its run's first peak; the significant contacts of
    /// the two runs are paired in order. Each difference is relative to the reference's value
    /// (0 where that value is 0).
    pub fn differences_from(&self, reference: &Report) -> Differences {
        let significant = SIGNIFICANT_PEAK;
        let relative = |a: f64, b: f64| if b == 0.0 { 0.0 } else { ((a - b) / b).abs() };
        let pick = |r: &'_ Report| -> Vec<Contact> {
            let first = r.contacts.first().map_or(0.0, |c| c.peak_force);
            r.contacts.iter().filter(|c| c.peak_force >= significant * first).cloned().collect()
        };
        let (mine, theirs) = (pick(self), pick(reference));
        let same_contacts = mine.len() == theirs.len();
        let mut sequence: f64 = if same_contacts { 0.0 } else { 1.0 };
        for (i, (a, b)) in mine.iter().zip(&theirs).enumerate() {
            sequence = sequence.max(relative(a.peak_force, b.peak_force));
            if i > 0 {
                sequence = sequence.max(relative(a.start, b.start));
            }
            if a.complete && b.complete {
                sequence = sequence.max(relative(a.duration, b.duration));
            }
        }
        let first =
            |f: fn(&Contact) -> f64| match (self.contacts.first(), reference.contacts.first()) {
                (Some(a), Some(b)) => relative(f(a), f(b)),
                (None, None) => 0.0,
                _ => 1.0,
            };
        Differences {
            first_duration: first(|c| c.duration),
            first_peak_force: first(|c| c.peak_force),
            contact_sequence: sequence.min(1.0),
            max_displacement: relative(self.max_displacement, reference.max_displacement),
            max_stress: match (&self.bending_stress, &reference.bending_stress) {
                (Some(a), Some(b)) => relative(a.max, b.max),
                _ => 0.0,
            },
            same_contacts,
        }
    }
}

/// Whether the largest displacement is not yet one: found at the last instant observed, still
/// growing, or in the window's last tenth while the first swing (the first contact's start
/// plus the first mode's quarter period) has not ended with the window. The ripple of later
/// contacts can put a local maximum just before the end of a window that stops mid-swing (the
/// paper's tip in aluminium, Timoshenko modes: at 4.97 of 5 ms, a quarter period being 50 ms).
fn displacement_at_window_end(plan: &Plan, end: &Ending) -> bool {
    let (max, time) = end.max_displacement;
    let swing_unfinished = match (plan.first_period, end.contacts.first()) {
        (Some(period), Some(first)) => first.start + 0.25 * period > end.last_time,
        _ => false,
    };
    max > 0.0 && (time >= end.last_time || (swing_unfinished && time >= 0.9 * end.last_time))
}

/// Where the largest displacement is not at the window's end but the ball strikes again, or
/// under gravity will, before the first swing has ended: the window is shorter than the first
/// contact's end plus half the first mode's period (the window the warnings advise for the
/// first swing). Returns (the first strike after the largest displacement, if within the
/// window; that window's end). The ball falling back strikes the swinging beam again and can
/// carry the swing further: the paper's tip over 0.1 s, its largest displacement at 75 ms,
/// peaks at 113 ms 16 % higher (h = 0.05 m, struck again at 87 ms) or 8 % (h = 0.1 m, struck
/// again only after the 0.1 s); 0.16 s holds it to the chatter's own spread
/// (validation/REFERENCES.md 1.15).
fn driven_swing(plan: &Plan, end: &Ending) -> Option<(Option<f64>, f64)> {
    let (max, time) = end.max_displacement;
    let first = end.contacts.first()?;
    let hold_until = first.start + first.duration + 0.5 * plan.first_period?;
    let strike = end.contacts.iter().find(|c| c.start > time).map(|c| c.start);
    let returns = strike.is_some() || plan.gravity > 0.0;
    (max > 0.0 && returns && end.last_time < hold_until).then_some((strike, hold_until))
}

/// Warnings for maxima at the window's end and for a stress past the beam's yield stress.
fn envelope_warnings(plan: &Plan, end: &Ending, warnings: &mut Vec<String>) {
    let window = plan.end_time;
    let quarter = plan.first_period.map(|t| 0.25 * t);
    let hold = |what: &str| {
        match quarter {
        Some(q) => format!(
            "the largest {what} sits at the window's end (t = {window:.4e} s) or close to it with the first swing unfinished, so it is not yet the maximum; the first mode's quarter period is {q:.4e} s, so solver.end_time = {:.4e} s (the first contact's end plus half a period) would hold the first swing",
            end.contacts.first().map_or(0.0, |c| c.start + c.duration) + 2.0 * q
        ),
        None => format!(
            "the largest {what} sits at the window's end (t = {window:.4e} s): it was still growing, so it is not yet the maximum; a longer solver.end_time would find a larger one"
        ),
    }
    };
    if displacement_at_window_end(plan, end) {
        warnings.push(hold("displacement at the impact point"));
    } else if let Some((strike, hold_until)) = driven_swing(plan, end) {
        let again = match strike {
            Some(t) => format!("the ball strikes again after it (at t = {t:.4e} s)"),
            None => "gravity brings the ball back to strike again".to_string(),
        };
        warnings.push(format!(
            "the largest displacement at the impact point (t = {:.4e} s) may not be the maximum: {again} before the first swing has ended (the first contact's end plus half the first mode's period, {hold_until:.4e} s), and such strikes drive the swing further (the paper's tip under gravity over 0.1 s: 3 to 16 % low for drop heights of 0.05 to 0.5 m; validation/REFERENCES.md 1.15); solver.end_time = {hold_until:.4e} s would hold the first swing",
            end.max_displacement.1
        ));
    }
    if let Some(s) = &end.bending_stress {
        if s.at_window_end {
            warnings.push(hold("bending stress"));
        }
        if let Some(ratio) = s.yield_ratio.filter(|r| *r > 1.0) {
            warnings.push(format!(
                "the beam's bending stress reaches {:.4e} Pa, {ratio:.3} times its yield stress, at {:.4e} m at t = {:.4e} s: the beam yields there, and beam plasticity is not modelled (the result past that instant is elastic)",
                s.max, s.position, s.time
            ));
        }
    }
}

/// The energy ledger's leftover as a share of the initial energy, past which the report warns:
/// the validation scenes close to 3e-5 to 1.3e-4 (fe: the paper's tip, the frame, the heavy
/// ball over 0.4 s) and 1e-9 (modal) of it; twenty times the worst is a run whose forces did
/// work no term holds (a ball started inside a face, a contact stepped too coarsely for its
/// stiffness), whose every number is in doubt.
const LEDGER_WARNING: f64 = 3e-3;

/// The share of the energy in play HHT-alpha's numerical damping may take before the report
/// warns: the default steps take 1e-4 of it or less.
const NUMERICAL_DAMPING_WARNING: f64 = 0.01;

/// Warns when the energy ledger does not close (see [`LEDGER_WARNING`]), as a share of the
/// energy in play: the initial energy plus the work gravity did on the ball (its potential
/// energy's fall below first touch). A ball set down at 1e-6 m/s under gravity sinks into the
/// contact with 4.5e-8 J of gravity's work against 1.6e-14 J of initial kinetic energy; a
/// round-off of 2e-15 J had been warned as 0.13 of the initial (a review's).
fn ledger_warning(energy: &Energy, warnings: &mut Vec<String>) {
    let in_play = energy.initial + (-energy.ball_potential).max(0.0);
    if energy.initial <= 0.0 || energy.initial.is_nan() || in_play.is_nan() {
        return;
    }
    let (of, what) = if in_play > energy.initial {
        (in_play, "the energy in play (the initial plus gravity's work)")
    } else {
        (energy.initial, "the initial energy")
    };
    let share = energy.balance_error / of;
    if share.abs() > LEDGER_WARNING || !share.is_finite() {
        warnings.push(format!(
            "the energy ledger does not close: {:.3e} J of {what}, {of:.3e} J ({share:.2e} of it), is in no term{}; a run whose forces did work that no term holds is not to be trusted (a contact stepped too coarsely for its stiffness, a ball started inside a face)",
            energy.balance_error,
            if energy.balance_error < 0.0 { ", energy made, not lost" } else { "" }
        ));
    }
    // HHT-alpha's damping of what the steps do not resolve: at the default steps 1e-4 of the
    // impact energy or less (the validation scenes); a long solver.time_step over a long
    // window took 28 % (a review's tip mass over 1.2 s at 2e-5 s), damping the structure's
    // response by the integrator, not its material.
    let taken = energy.numerical_dissipation / of;
    if taken > NUMERICAL_DAMPING_WARNING {
        warnings.push(format!(
            "HHT-alpha's numerical damping took {:.3e} J ({:.1} % of {what}): the steps are long for the waves the impact leaves, which the integrator damps where the material would not; shorter steps (solver.time_step, or its default) or solver.alpha = 0 keep them",
            energy.numerical_dissipation,
            100.0 * taken
        ));
    }
    // HHT-alpha with alpha <= 0 takes energy out of a linear system, never puts it in: a
    // negative numerical dissipation is the contact's nonlinearity stepped too coarsely.
    let made = -energy.numerical_dissipation / of;
    if made > LEDGER_WARNING {
        warnings.push(format!(
            "the time integration made {:.3e} J ({made:.2e} of {what}; numerical_dissipation is negative): HHT-alpha only takes energy out of a linear system, so the contact was stepped too coarsely for its stiffness; more solver.samples_per_pulse (shorter contact steps) would show whether the results hold",
            -energy.numerical_dissipation
        ));
    }
}

/// Fills in the contact's pressure, radius and subsurface shear at its peak force, with the
/// ball's and the body's largest shear per unit pressure and its depth per unit radius.
fn contact_stresses(plan: &Plan, [ball, body]: [(f64, f64); 2], c: &mut Contact) {
    let (p0, a) = plan.law.peak_pressure(c.peak_force, c.max_approach, c.print_radius);
    c.max_pressure = p0;
    c.contact_radius = a;
    (c.ball_max_shear, c.ball_max_shear_depth) = (ball.0 * p0, ball.1 * a);
    (c.body_max_shear, c.body_max_shear_depth) = (body.0 * p0, body.1 * a);
}

/// Hertz's theory (and Thornton's on it) holds for a contact radius small against the ball's
/// radius, a = sqrt(R delta) < 0.3 R (delta < 0.09 R), and an approach small against what it
/// presses into (a tenth of the beam's thickness); a print is a contact radius too. Past either
/// the numbers are extrapolations: say so, with the first contact that goes past.
fn small_strain_warnings(plan: &Plan, contacts: &[Contact], warnings: &mut Vec<String>) {
    let radius = plan.ball_radius;
    if let Some((i, c)) = contacts
        .iter()
        .enumerate()
        .find(|(_, c)| c.max_approach > 0.09 * radius || c.print_radius > 0.3 * radius)
    {
        warnings.push(format!(
            "contact {}: approach {:.3e} m (contact radius sqrt(R delta) = {:.3e} m) and print radius {:.3e} m against a ball radius of {radius:.3e} m: beyond small-strain contact (approach < 0.09 R, contact radius < 0.3 R), the contact law is extrapolated",
            i + 1,
            c.max_approach,
            (radius * c.max_approach.max(0.0)).sqrt(),
            c.print_radius
        ));
    }
    // Hertz's contact radius a = sqrt(R delta) of a sphere on a flat face: beyond the beam's
    // half-width the patch runs over the face's edge, where no half-space holds.
    if let Some(width) = plan.width {
        if let Some((i, c)) = contacts
            .iter()
            .enumerate()
            .find(|(_, c)| (radius * c.max_approach.max(0.0)).sqrt() > 0.5 * width)
        {
            let a = (radius * c.max_approach).sqrt();
            warnings.push(format!(
                "contact {}: the contact radius sqrt(R delta) = {a:.3e} m is {:.2} times the beam's half-width {:.3e} m: the contact patch runs over the face's edges, where the contact law (a half-space) does not hold",
                i + 1,
                a / (0.5 * width),
                0.5 * width
            ));
        }
    }
    if let Some(thickness) = plan.thickness {
        if let Some((i, c)) =
            contacts.iter().enumerate().find(|(_, c)| c.max_approach > 0.1 * thickness)
        {
            warnings.push(format!(
                "contact {}: approach {:.3e} m is more than a tenth of the beam's thickness {thickness:.3e} m: the beam is not a half-space under the ball, the contact law is extrapolated",
                i + 1,
                c.max_approach
            ));
        }
    }
}

/// Static stiffness (N/m) from the static flexibility at the impact point (m/N), or a warning
/// when there is none.
pub(crate) fn static_stiffness(
    flexibility: Option<f64>,
    warnings: &mut Vec<String>,
) -> Option<f64> {
    match flexibility {
        Some(f) if f > 0.0 => Some(1.0 / f),
        _ => {
            // Said once: the plan may have named the mechanism already.
            if !warnings.iter().any(|w| w.contains("no static stiffness")) {
                warnings.push("no static stiffness at the impact point (the beam or structure is not held there against a static force: a free body, a mechanism, or a point its supports hold): no equivalent static force".into());
            }
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ledger_that_does_not_close_or_energy_the_integration_made_warns() {
        let warn = |e: Energy| {
            let mut w = Vec::new();
            ledger_warning(&e, &mut w);
            w
        };
        // The paper's tip by the fe method: closes to 3e-5, its numerical dissipation 4e-5.
        let closed = Energy::new(1.7658e-2, 1.205e-4, 0.0, 1.7536e-2, 4.0e-7, 0.0, 7.0e-7);
        assert!(warn(closed).is_empty());
        // The review's arc: -3.3e3 of the initial energy left over (made), and some by the
        // integration too.
        let made = Energy::new(1.7658e-2, 48.39, 0.0, 10.56, 0.0, 0.0, -2.37e-3);
        let w = warn(made);
        assert!(w.len() == 2 && w[0].contains("energy made"), "{w:?}");
        // The 1 um ball before its rows balanced: the ledger closed, the integration made it.
        let (initial, made) = (6.451449e-14, 4.266058e-9);
        let hidden = Energy::new(initial, initial + made, 0.0, 0.0, 0.0, 0.0, -made);
        let w = warn(hidden);
        assert!(w.len() == 1 && w[0].contains("numerical_dissipation is negative"), "{w:?}");
        // No initial energy (a ball at rest): nothing to compare with, no warning.
        assert!(warn(Energy::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)).is_empty());
    }
}
