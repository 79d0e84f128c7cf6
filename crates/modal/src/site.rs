//! A modal basis seen from one contact site, whatever computed it: what Goldsmith's method
//! steps and what it reads back.
//!
//! The contact step needs, of any basis (the analytic uniform beam's or modes computed from a
//! finite-element model of a structure), the frequencies, damping ratios and gains at the site
//! ([`PointModes`]) and the site's static flexibility, whose excess over the kept modes' share
//! is the residual flexibility put in series with the contact (the mode-acceleration method,
//! validation/REFERENCES.md 1.4). A recovery ([`Recovery`]) reads other quantities that are
//! linear in the beam's motion (section strains, twists, displacements elsewhere) from the
//! modal coordinates and the contact force in the same mode-acceleration form.

use crate::error::ModalError;
use crate::propagate::PointModes;

/// The kept modes at the contact site and the site's static flexibility.
#[derive(Debug, Clone, PartialEq)]
pub struct SiteModes {
    modes: PointModes,
    static_flexibility: Option<f64>,
    residual: Option<f64>,
}

impl SiteModes {
    /// The kept `modes` at the site and its static flexibility (m/N), `None` where the
    /// structure has none (a free body).
    ///
    /// # Errors
    /// `InvalidParameter` if the flexibility is not finite and at least 0 (0 where a support
    /// holds the site), or if the kept modes' share `sum g_n^2 / omega_n^2` exceeds it by more than round-off: the modes are not
    /// those of the structure whose static flexibility this is.
    pub fn new(modes: PointModes, static_flexibility: Option<f64>) -> Result<Self, ModalError> {
        let residual = static_flexibility.map(|f| (f - modes.static_flexibility()).max(0.0));
        Self::with_residual(modes, static_flexibility, residual)
    }

    /// As [`SiteModes::new`], with the residual flexibility (m/N) computed by the basis
    /// itself. A basis whose low modes carry round-off of the stiffness' spread (a slender
    /// finite-element strip: ~1e-7 of the flexibility, as large as the residual) solves it
    /// directly from the load with the kept modes taken out, r' K^-1 r' with
    /// r' = r - M Phi Phi^T r, where the difference `f - sum g^2/omega^2` would be round-off.
    ///
    /// # Errors
    /// `InvalidParameter` if a flexibility is not finite and at least 0, or a residual is
    /// given without a static flexibility.
    pub fn with_residual(
        modes: PointModes,
        static_flexibility: Option<f64>,
        residual: Option<f64>,
    ) -> Result<Self, ModalError> {
        for (name, value) in [("static_flexibility", static_flexibility), ("residual", residual)] {
            if let Some(f) = value.filter(|f| !(f.is_finite() && *f >= 0.0)) {
                return Err(ModalError::InvalidParameter {
                    name,
                    value: f,
                    unit: "m/N",
                    allowed: "a finite number >= 0",
                });
            }
        }
        if residual.is_some() && static_flexibility.is_none() {
            return Err(ModalError::InvalidParameter {
                name: "residual",
                value: residual.unwrap_or(0.0),
                unit: "m/N",
                allowed: "none without a static flexibility (a free body)",
            });
        }
        Ok(Self { modes, static_flexibility, residual })
    }

    /// The kept modes at the site.
    pub fn modes(&self) -> &PointModes {
        &self.modes
    }

    /// The kept modes, taken out (what a solver steps).
    pub fn into_modes(self) -> PointModes {
        self.modes
    }

    /// The site's static flexibility (m/N), `None` for a free body.
    pub fn static_flexibility(&self) -> Option<f64> {
        self.static_flexibility
    }

    /// What the truncated modes add to the site's static flexibility (m/N): the static
    /// flexibility less the kept modes' share, at least 0 (round-off takes a held site's
    /// below); `None` for a free body.
    pub fn residual_flexibility(&self) -> Option<f64> {
        self.residual
    }
}

/// Quantities linear in the beam's motion, read from the modal coordinates q and the contact
/// force F in the mode-acceleration form: value_k = sum_n r_kn q_n + p_k F, with p_k the
/// quantity under a unit static force at the site carried by the truncated modes
/// (s_k - sum_n r_kn g_n / omega_n^2, s_k the whole static value; a basis may solve it
/// directly, see [`SiteModes::with_residual`]) or 0 for the plain series.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovery {
    /// Modes per row.
    modes: usize,
    /// r_kn, mode-major (a mode's rows together): evaluated as one scaled column added per
    /// mode, which vectorises (a row-major dot product per row did not: three quarters of a
    /// 2 ms frame run by perf, 4x slower).
    columns: Vec<f64>,
    /// p_k.
    force: Vec<f64>,
}

impl Recovery {
    /// The rows `rows` (row-major, `modes.len()` a row) over the kept `modes`, with the
    /// truncated modes' static share `truncated` (one a row: p_k) for the mode-acceleration
    /// form, or `None` for the plain series.
    ///
    /// # Errors
    /// `InvalidParameter` if the rows' length is not a multiple of the modes, the shares are
    /// not one a row, or a value is not finite.
    pub fn new(
        modes: &PointModes,
        rows: Vec<f64>,
        truncated: Option<&[f64]>,
    ) -> Result<Self, ModalError> {
        let n = modes.len();
        let count = rows.len().checked_div(n).unwrap_or(0);
        let bad = |name, value: f64, allowed| ModalError::InvalidParameter {
            name,
            value,
            unit: "-",
            allowed,
        };
        if n == 0 || rows.len() != count * n {
            return Err(bad("rows", rows.len() as f64, "a whole number of rows over the modes"));
        }
        if let Some(&v) = rows.iter().find(|v| !v.is_finite()) {
            return Err(bad("rows", v, "finite values"));
        }
        let force = match truncated {
            None => vec![0.0; count],
            Some(p) if p.len() != count => {
                return Err(bad("truncated", p.len() as f64, "one share a row"))
            }
            Some(p) => p.to_vec(),
        };
        if let Some(&v) = force.iter().find(|v| !v.is_finite()) {
            return Err(bad("truncated", v, "finite values"));
        }
        let columns = (0..n)
            .flat_map(|m| (0..count).map(move |k| (k, m)))
            .map(|(k, m)| rows[k * n + m])
            .collect();
        Ok(Self { modes: n, columns, force })
    }

    /// How many quantities.
    pub fn len(&self) -> usize {
        self.force.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.force.is_empty()
    }

    /// Every quantity at the modal coordinates `q` under the contact force `force` (N), into
    /// `out` (one a row).
    ///
    /// # Panics
    /// If `out` does not hold one value a row or `q` one a mode.
    pub fn evaluate(&self, q: &[f64], force: f64, out: &mut [f64]) {
        let count = self.force.len();
        assert!(out.len() == count && q.len() == self.modes, "one value a row and one a mode");
        crate::on_four_lanes(Evaluate { recovery: self, q, force, out });
    }
}

/// [`Recovery::evaluate`]'s loops, compiled for the processor's vectors (`on_four_lanes`): one
/// scaled column added per mode.
struct Evaluate<'a> {
    recovery: &'a Recovery,
    q: &'a [f64],
    force: f64,
    out: &'a mut [f64],
}

impl pulp::WithSimd for Evaluate<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Self { recovery, q, force, out } = self;
        for (o, p) in out.iter_mut().zip(&recovery.force) {
            *o = p * force;
        }
        for (column, q) in recovery.columns.chunks_exact(recovery.force.len()).zip(q) {
            for (o, r) in out.iter_mut().zip(column) {
                *o += r * q;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn modes() -> PointModes {
        PointModes::from_parts(vec![0.0, 2.0, 4.0], vec![0.0; 3], vec![1.0, 0.5, 0.25])
            .unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn the_residual_is_the_static_flexibility_less_the_kept_share() {
        // Kept share: 0.5^2/4 + 0.25^2/16 = 0.06640625 (the rigid mode has none).
        let site = SiteModes::new(modes(), Some(0.1)).unwrap_or_else(|e| panic!("{e}"));
        let residual = site.residual_flexibility().unwrap_or(f64::NAN);
        assert!((residual - (0.1 - 0.06640625)).abs() < 1e-15, "{residual}");
        let held = SiteModes::new(modes(), Some(0.0)).map(|s| s.residual_flexibility());
        assert_eq!(held, Ok(Some(0.0)));
        assert!(SiteModes::new(modes(), Some(f64::NAN)).is_err());
        assert!(SiteModes::new(modes(), Some(-1.0)).is_err());
        assert_eq!(SiteModes::new(modes(), None).map(|s| s.residual_flexibility()), Ok(None));
        let given = SiteModes::with_residual(modes(), Some(0.1), Some(1e-3));
        assert_eq!(given.map(|s| s.residual_flexibility()), Ok(Some(1e-3)));
        assert!(SiteModes::with_residual(modes(), None, Some(1e-3)).is_err());
        assert!(SiteModes::with_residual(modes(), Some(0.1), Some(-1e-3)).is_err());
    }

    #[test]
    fn a_recovery_row_adds_the_truncated_modes_static_share() {
        // One row r = (1, 2, 3) with the truncated modes' share 0.5 under a force of 2.
        let modes = modes();
        let rows = Recovery::new(&modes, vec![1.0, 2.0, 3.0], Some(&[0.5]))
            .unwrap_or_else(|e| panic!("{e}"));
        let q = [0.1, 0.2, 0.3];
        let expected = 0.1 + 0.4 + 0.9 + 0.5 * 2.0;
        let mut out = [0.0];
        rows.evaluate(&q, 2.0, &mut out);
        assert!((out[0] - expected).abs() < 1e-15);
        assert!(Recovery::new(&modes, vec![1.0, 2.0], None).is_err());
        assert!(Recovery::new(&modes, vec![1.0, 2.0, f64::NAN], None).is_err());
        assert!(Recovery::new(&modes, vec![1.0, 2.0, 3.0], Some(&[1.0, 2.0])).is_err());
    }
}
