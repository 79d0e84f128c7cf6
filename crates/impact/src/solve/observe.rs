//! One way a solver hands its state to what records it.
//!
//! At every recorded instant a solver builds an [`Instant`]: the history's row and a view of
//! its beam ([`BeamView`]: the modal coordinates with the contact force, or the fe beam in its
//! configuration), and hands it to its [`Recorders`]. The history, the progress, and the
//! beam's recovery (the stress envelope and, on request, the field: [`BeamRecorder`]) are its
//! users; the fe solver also hands over every accepted step without a row, for the envelope.
//! A new output is a new user here, not a new column in each solver.

use super::Progress;
use crate::outcome::{BendingStress, Field, History, Sample};
use simo_beam::PlanarState;

/// What a solver shows of its beam.
pub(crate) enum BeamView<'a> {
    /// The modal beam: its modal coordinates, their rates and the contact force (N) on it.
    Modal { q: &'a [f64], v: &'a [f64], force: f64 },
    /// The fe beam in its configuration, with each element's section strains (extension,
    /// shear, curvature (1/m)) in it, computed once for all their users, and (the 3D beam)
    /// each element's stress from its bending about the thickness axis, E (w/2) |K3| (Pa),
    /// which adds to the largest corner's; its displacements and slopes (the field's) only at
    /// a recorded instant of a run that records the field.
    Fe { state: Option<&'a PlanarState>, strains: &'a [(f64, f64, f64)], lateral: &'a [f64] },
}

/// One instant of a run.
pub(crate) struct Instant<'a> {
    /// Time (s).
    pub(crate) t: f64,
    /// The history's row at a recorded instant; `None` at an instant only the envelopes see.
    pub(crate) sample: Option<Sample>,
    /// The beam.
    pub(crate) beam: BeamView<'a>,
    /// Whether it is the run's final instant.
    pub(crate) last: bool,
}

/// A recovery of the beam's state: the stress envelope and the field.
pub(crate) trait BeamRecorder {
    /// Takes the beam at one instant (views of another method are ignored).
    fn observe(&mut self, at: &Instant<'_>);
    /// A step of the solver ended at `t` (s) with the contact force `force` (N), the force
    /// linear in time since the step before: what a search between instants needs (the modal
    /// method's; others ignore it).
    fn step(&mut self, _t: f64, _force: f64) {}
    /// When it next wants to see the beam (s): a solver that can end a step there (the modal
    /// one in free flight) does, and hands it an instant without a sample.
    fn next_look(&self) -> f64 {
        f64::INFINITY
    }
    /// The stress envelope, with `yield_stress` (Pa) for its ratio.
    fn finish(&mut self, yield_stress: Option<f64>) -> BendingStress;
    /// The largest displacement at the impact point (m) and when (s), given the largest the
    /// solver saw (`seen`): a recovery that searches between instants raises it.
    fn displacement_peak(&mut self, seen: (f64, f64)) -> (f64, f64) {
        seen
    }
    /// The struck section's largest twist magnitude (rad) and when (s), for an off-centre
    /// strike (after [`BeamRecorder::finish`]).
    fn twist_peak(&self) -> Option<(f64, f64)> {
        None
    }
    /// The largest twist of any section (rad), where (m) and when (s), where the recovery
    /// reads every node's (a structure's modes).
    fn largest_twist_peak(&self) -> Option<(f64, f64, f64)> {
        None
    }
    /// The largest Saint-Venant shear stress of torsion (Pa), where (m) and when (s), for an
    /// off-centre strike (after [`BeamRecorder::finish`]).
    fn torsion_shear_peak(&self) -> Option<(f64, f64, f64)> {
        None
    }
    /// What the report's reasons say of how the maxima were found, if anything.
    fn search_note(&self) -> Option<String> {
        None
    }
    /// Warnings of maxima the recovery could not make certain.
    fn search_warnings(&self) -> Vec<String> {
        Vec::new()
    }
    /// The recorded field, if it was asked for.
    fn take_field(&mut self) -> Option<Field>;
}

/// What the recovery hands back at the end of a run.
pub(crate) struct Recovered {
    pub(crate) history: History,
    pub(crate) stress: Option<BendingStress>,
    pub(crate) field: Option<Field>,
    /// The largest displacement at the impact point (m) and when (s).
    pub(crate) displacement: (f64, f64),
    /// The struck section's largest twist (rad) and when (s), for an off-centre strike.
    pub(crate) twist: Option<(f64, f64)>,
    /// The largest twist of any section (rad), where (m) and when (s), if read.
    pub(crate) largest_twist: Option<(f64, f64, f64)>,
    /// The largest torsion shear stress (Pa), where (m) and when (s), for an off-centre strike.
    pub(crate) torsion_shear: Option<(f64, f64, f64)>,
    /// How the maxima were found, for the report's reasons, and what could not be made
    /// certain, for its warnings.
    pub(crate) note: Option<String>,
    pub(crate) warnings: Vec<String>,
}

/// The users of a run's instants.
pub(crate) struct Recorders<'a> {
    pub(crate) history: History,
    progress: Progress<'a>,
    end_time: f64,
    beam: Option<Box<dyn BeamRecorder + 'a>>,
}

impl<'a> Recorders<'a> {
    /// The recorders of a run over `end_time` (s): a `history`, the `progress` (told the
    /// fraction of the window at each recorded instant) and the beam's recovery, if any.
    pub(crate) fn new(
        history: History,
        progress: Progress<'a>,
        end_time: f64,
        beam: Option<Box<dyn BeamRecorder + 'a>>,
    ) -> Self {
        Self { history, progress, end_time, beam }
    }

    /// Hands `at` to every user.
    pub(crate) fn observe(&mut self, at: Instant<'_>) {
        if let Some(beam) = &mut self.beam {
            beam.observe(&at);
        }
        if let Some(sample) = at.sample {
            (self.progress)(at.t / self.end_time);
            self.history.push(sample);
        }
    }

    /// The beam's recovery replaced by `wrap` of it (a test that watches what a solver hands
    /// over).
    #[cfg(test)]
    pub(crate) fn wrap_beam(
        &mut self,
        wrap: impl FnOnce(Box<dyn BeamRecorder + 'a>) -> Box<dyn BeamRecorder + 'a>,
    ) {
        self.beam = self.beam.take().map(wrap);
    }

    /// When the beam's recovery next wants to see the beam (see [`BeamRecorder::next_look`]).
    pub(crate) fn next_look(&self) -> f64 {
        self.beam.as_ref().map_or(f64::INFINITY, |b| b.next_look())
    }

    /// A solver step ended at `t` with the force `force` (see [`BeamRecorder::step`]).
    pub(crate) fn step(&mut self, t: f64, force: f64) {
        if let Some(beam) = &mut self.beam {
            beam.step(t, force);
        }
    }

    /// The last recorded instant (s).
    pub(crate) fn last_time(&self) -> f64 {
        self.history.time.last().copied().unwrap_or(0.0)
    }

    /// The history, the stress envelope, the field and the largest displacement (given the
    /// largest the solver saw, `displacement`).
    pub(crate) fn finish(
        mut self,
        yield_stress: Option<f64>,
        displacement: (f64, f64),
    ) -> Recovered {
        let stress = self.beam.as_mut().map(|b| b.finish(yield_stress));
        let displacement =
            self.beam.as_mut().map_or(displacement, |b| b.displacement_peak(displacement));
        let twist = self.beam.as_ref().and_then(|b| b.twist_peak());
        let largest_twist = self.beam.as_ref().and_then(|b| b.largest_twist_peak());
        let torsion_shear = self.beam.as_ref().and_then(|b| b.torsion_shear_peak());
        let note = self.beam.as_ref().and_then(|b| b.search_note());
        let warnings = self.beam.as_ref().map(|b| b.search_warnings()).unwrap_or_default();
        let field = self.beam.as_mut().and_then(|b| b.take_field());
        Recovered {
            history: self.history,
            stress,
            field,
            displacement,
            twist,
            largest_twist,
            torsion_shear,
            note,
            warnings,
        }
    }
}
