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
    /// The modal beam: its modal coordinates and the contact force (N) on it.
    Modal { q: &'a [f64], force: f64 },
    /// The fe beam in its configuration, with each element's section strains (extension,
    /// shear, curvature (1/m)) in it, computed once for all their users.
    Fe { state: &'a PlanarState, strains: &'a [(f64, f64, f64)] },
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
    /// The stress envelope, with `yield_stress` (Pa) for its ratio.
    fn finish(&self, yield_stress: Option<f64>) -> BendingStress;
    /// The recorded field, if it was asked for.
    fn take_field(&mut self) -> Option<Field>;
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

    /// Whether the beam is recovered (a beam, not a rigid block).
    pub(crate) fn has_beam(&self) -> bool {
        self.beam.is_some()
    }

    /// The last recorded instant (s).
    pub(crate) fn last_time(&self) -> f64 {
        self.history.time.last().copied().unwrap_or(0.0)
    }

    /// The history, the stress envelope and the field.
    pub(crate) fn finish(
        mut self,
        yield_stress: Option<f64>,
    ) -> (History, Option<BendingStress>, Option<Field>) {
        let stress = self.beam.as_ref().map(|b| b.finish(yield_stress));
        let field = self.beam.as_mut().and_then(|b| b.take_field());
        (self.history, stress, field)
    }
}
