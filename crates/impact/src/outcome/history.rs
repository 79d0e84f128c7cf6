//! Time histories of a run.

use serde::Serialize;
use std::io::Write;

/// Time series of one run, one row per recorded instant (SI units).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct History {
    /// Time since first touch t (s).
    pub time: Vec<f64>,
    /// Contact force F (N), compressive positive.
    pub force: Vec<f64>,
    /// Approach delta (m), positive in compression (ball into the surface).
    pub approach: Vec<f64>,
    /// Ball displacement toward the beam since first touch (m).
    pub ball_position: Vec<f64>,
    /// Ball velocity toward the beam (m/s).
    pub ball_velocity: Vec<f64>,
    /// Beam displacement at the impact point, in the direction of impact (m).
    pub beam_displacement: Vec<f64>,
    /// Where the ball touches (or is nearest to) the beam, as the reference position along
    /// the beam from x = 0 (m): fixed at the impact point in the modal method, sliding in the
    /// finite-element method; 0 on a half-space.
    pub contact_point: Vec<f64>,
    /// Ball energy, kinetic + gravitational potential from the first-touch height (J).
    pub ball_energy: Vec<f64>,
    /// Beam energy, kinetic + strain (J); 0 on a half-space.
    pub beam_energy: Vec<f64>,
    /// Elastic energy stored in the contact (J).
    pub contact_energy: Vec<f64>,
    /// Energy dissipated so far: plastic work, contact damping and modal damping (J).
    pub dissipated_energy: Vec<f64>,
}

/// One row of a [`History`] (the same fields and units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time since first touch (s).
    pub time: f64,
    /// Contact force (N).
    pub force: f64,
    /// Approach (m).
    pub approach: f64,
    /// Ball displacement toward the beam since first touch (m).
    pub ball_position: f64,
    /// Ball velocity toward the beam (m/s).
    pub ball_velocity: f64,
    /// Beam displacement at the impact point (m).
    pub beam_displacement: f64,
    /// Reference position of the contact point along the beam (m).
    pub contact_point: f64,
    /// Ball energy (J).
    pub ball_energy: f64,
    /// Beam energy (J).
    pub beam_energy: f64,
    /// Energy stored in the contact (J).
    pub contact_energy: f64,
    /// Energy dissipated so far (J).
    pub dissipated_energy: f64,
}

impl Sample {
    /// A row with the energy columns taken from the ledger `energy`.
    #[allow(clippy::too_many_arguments)] // one per column; the call sites name each
    pub(crate) fn with_energy(
        time: f64,
        force: f64,
        approach: f64,
        ball_position: f64,
        ball_velocity: f64,
        beam_displacement: f64,
        contact_point: f64,
        energy: &crate::outcome::Energy,
    ) -> Self {
        Self {
            time,
            force,
            approach,
            ball_position,
            ball_velocity,
            beam_displacement,
            contact_point,
            ball_energy: energy.ball_kinetic + energy.ball_potential,
            beam_energy: energy.beam,
            contact_energy: energy.contact_stored,
            dissipated_energy: energy.dissipated,
        }
    }
}

impl History {
    /// Empty, with room for `rows` rows: a run that knows roughly how many it will record
    /// grows its columns once instead of a dozen times.
    pub fn with_capacity(rows: usize) -> Self {
        let column = || Vec::with_capacity(rows);
        Self {
            time: column(),
            force: column(),
            approach: column(),
            ball_position: column(),
            ball_velocity: column(),
            beam_displacement: column(),
            contact_point: column(),
            ball_energy: column(),
            beam_energy: column(),
            contact_energy: column(),
            dissipated_energy: column(),
        }
    }

    /// Appends one row.
    pub fn push(&mut self, s: Sample) {
        self.time.push(s.time);
        self.force.push(s.force);
        self.approach.push(s.approach);
        self.ball_position.push(s.ball_position);
        self.ball_velocity.push(s.ball_velocity);
        self.beam_displacement.push(s.beam_displacement);
        self.contact_point.push(s.contact_point);
        self.ball_energy.push(s.ball_energy);
        self.beam_energy.push(s.beam_energy);
        self.contact_energy.push(s.contact_energy);
        self.dissipated_energy.push(s.dissipated_energy);
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True if nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The history's columns, each named as in its CSV with its unit (`time_s`, `force_n`,
    /// ...): what every front end (the CSV, Python's arrays) shows.
    pub fn columns(&self) -> [(&'static str, &[f64]); 11] {
        [
            ("time_s", &self.time),
            ("force_n", &self.force),
            ("approach_m", &self.approach),
            ("ball_position_m", &self.ball_position),
            ("ball_velocity_m_s", &self.ball_velocity),
            ("beam_displacement_m", &self.beam_displacement),
            ("contact_point_m", &self.contact_point),
            ("ball_energy_j", &self.ball_energy),
            ("beam_energy_j", &self.beam_energy),
            ("contact_energy_j", &self.contact_energy),
            ("dissipated_energy_j", &self.dissipated_energy),
        ]
    }

    /// Writes the history as CSV with the unit in every column name.
    ///
    /// # Errors
    /// Any I/O error of the writer.
    pub fn write_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        let columns = self.columns();
        let names: Vec<&str> = columns.iter().map(|(name, _)| *name).collect();
        writeln!(w, "{}", names.join(","))?;
        for i in 0..self.len() {
            for (c, (_, v)) in columns.iter().enumerate() {
                let separator = if c == 0 { "" } else { "," };
                write!(w, "{separator}{:.9e}", v[i])?;
            }
            writeln!(w)?;
        }
        Ok(())
    }
}
