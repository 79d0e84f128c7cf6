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
}

impl History {
    /// Appends one row.
    pub fn push(
        &mut self,
        t: f64,
        force: f64,
        approach: f64,
        ball_position: f64,
        ball_velocity: f64,
        beam: f64,
    ) {
        self.time.push(t);
        self.force.push(force);
        self.approach.push(approach);
        self.ball_position.push(ball_position);
        self.ball_velocity.push(ball_velocity);
        self.beam_displacement.push(beam);
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True if nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Writes the history as CSV with the unit in every column name.
    ///
    /// # Errors
    /// Any I/O error of the writer.
    pub fn write_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        writeln!(
            w,
            "time_s,force_n,approach_m,ball_position_m,ball_velocity_m_s,beam_displacement_m"
        )?;
        for i in 0..self.len() {
            writeln!(
                w,
                "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
                self.time[i],
                self.force[i],
                self.approach[i],
                self.ball_position[i],
                self.ball_velocity[i],
                self.beam_displacement[i]
            )?;
        }
        Ok(())
    }
}
