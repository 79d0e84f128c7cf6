//! The beam's field: displacement, slope, bending moment and stress along the beam at the
//! recorded instants, from the same recovery as the report's stress maxima.

/// The beam along its length at each recorded instant (written on request: see
/// [`crate::Plan::with_field`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Field {
    /// The points along the beam (m, from the end at x = 0).
    pub points: Vec<f64>,
    /// The instants (s).
    pub time: Vec<f64>,
    /// Displacement w (m, positive away from the ball), one row of `points` an instant.
    pub displacement: Vec<f64>,
    /// Slope dw/dx (-).
    pub slope: Vec<f64>,
    /// Bending moment M = EI w'' (N m).
    pub moment: Vec<f64>,
    /// Outer-fibre stress on the struck face (Pa), tension positive (the fe method's includes
    /// the axial stress N/A).
    pub stress: Vec<f64>,
}

impl Field {
    /// An empty field over `points`.
    pub(crate) fn new(points: Vec<f64>) -> Self {
        Self { points, ..Self::default() }
    }

    /// Adds the instant `t` (s); the caller pushes one value a point into each column.
    pub(crate) fn push_instant(&mut self, t: f64) {
        self.time.push(t);
    }

    /// Writes the field as CSV, long format: `time_s, x_m, displacement_m, slope_rad,
    /// moment_n_m, stress_pa`, one row a point and instant.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn write_csv(&self, mut out: impl std::io::Write) -> std::io::Result<()> {
        let quantities = self.quantities();
        let names: Vec<&str> = quantities.iter().map(|(name, _)| *name).collect();
        writeln!(out, "time_s,x_m,{}", names.join(","))?;
        let p = self.points.len();
        for (i, t) in self.time.iter().enumerate() {
            for (k, x) in self.points.iter().enumerate() {
                write!(out, "{t:.9e},{x:.6e}")?;
                for (_, v) in &quantities {
                    write!(out, ",{:.9e}", v[i * p + k])?;
                }
                writeln!(out)?;
            }
        }
        out.flush()
    }

    /// The recorded quantities, each named as its CSV column with its unit, each row-major
    /// over (instant, point): value `i * points.len() + k` is at `time[i]`, `points[k]`.
    pub fn quantities(&self) -> [(&'static str, &[f64]); 4] {
        [
            ("displacement_m", &self.displacement),
            ("slope_rad", &self.slope),
            ("moment_n_m", &self.moment),
            ("stress_pa", &self.stress),
        ]
    }

    /// The displacement history at the point nearest `x` (m): (time, w) pairs.
    pub fn displacement_at(&self, x: f64) -> Vec<(f64, f64)> {
        let Some(k) = (0..self.points.len())
            .min_by(|a, b| (self.points[*a] - x).abs().total_cmp(&(self.points[*b] - x).abs()))
        else {
            return Vec::new();
        };
        let p = self.points.len();
        self.time.iter().enumerate().map(|(i, t)| (*t, self.displacement[i * p + k])).collect()
    }
}
