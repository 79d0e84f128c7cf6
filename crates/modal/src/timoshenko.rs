//! Natural modes of a uniform Timoshenko beam: shear deformation and rotary inertia.
//!
//! kGA (w'' - psi') = rho A w-double-dot and EI psi'' + kGA (w' - psi) = rho I psi-double-dot
//! (Timoshenko 1921; validation/REFERENCES.md 1.6). A solution e^(lambda x) at frequency omega has
//!
//! lambda^4 + omega^2 (rho I/EI + rho A/kGA) lambda^2 + (rho A omega^2/EI)(rho I omega^2/kGA - 1) = 0,
//!
//! one root lambda^2 = -beta^2 (a travelling bending wave) and one s = alpha^2 that is positive
//! below the cut-off omega_c = sqrt(kGA / rho I) (an evanescent pair) and negative above it (a
//! second, shear, travelling wave). The section rotation of e^(lambda x) is
//! Psi = (lambda^2 + rho A omega^2/kGA)/lambda W.
//!
//! **Counting.** The number of natural frequencies below omega is found exactly by the
//! Wittrick-Williams algorithm (Wittrick & Williams 1971): the beam is cut into equal segments
//! short enough that a clamped segment has no natural frequency below omega (a Rayleigh-quotient
//! bound, below), so the count is the number of negative pivots of the assembled exact dynamic
//! stiffness. No root is missed, whether the branches cross or not.
//!
//! **Roots.** Between two counts the determinant of the four end conditions, written in bounded
//! waves with each row scaled to its largest entry, is scanned; when its sign changes as often as
//! the count says, each change is polished (Illinois), otherwise the interval is halved by
//! counts. Roots closer than the counts can split are one multiple root with as many shapes.

use crate::error::ModalError;
use crate::shape::{ModeShape, Wave};
use crate::support::Support;
use nalgebra::Matrix4;
use num_complex::Complex64;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The fewest roots in an interval whose halves are searched side by side.
const SIDE_BY_SIDE: usize = 16;

/// A uniform Timoshenko beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Timoshenko {
    pub(crate) ei: f64,
    pub(crate) rho_a: f64,
    pub(crate) kga: f64,
    pub(crate) rho_i: f64,
    pub(crate) length: f64,
    pub(crate) support: Support,
}

/// The two wave families at one frequency.
#[derive(Debug, Clone, Copy)]
struct Waves {
    /// Bending wavenumber (1/m).
    beta: f64,
    /// alpha^2 of the second pair (1/m^2): > 0 below the cut-off, < 0 above.
    s: f64,
    /// Psi/W factor of the second pair: Psi = sigma/lambda W, sigma = s + rho A omega^2/kGA.
    sigma: f64,
    /// Psi of the bending pair: W = cos(beta x) has Psi = q sin(beta x), q = (rho A omega^2/kGA - beta^2)/beta.
    q: f64,
}

/// Which bounded functions carry the second pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Basis {
    /// e^(-alpha x) and e^(alpha (x - L)): well separated when alpha L is large.
    Exponential,
    /// cosh(alpha x) and alpha sinh(alpha x) (cos and -k sin above the cut-off): entire in
    /// alpha^2, so continuous through the cut-off, and bounded while alpha L is moderate.
    Entire,
}

/// alpha L above which the exponential basis is used, below which the entire one.
const EXPONENTIAL_FROM: f64 = 3.0;
/// The entire basis is not used past this alpha L (cosh(30) ~ 5e12 loses digits).
const ENTIRE_UP_TO: f64 = 30.0;

/// W, W', Psi, Psi' and the shear strain W' - Psi of one basis function at one point. The shear
/// strain is formed directly: as a difference it would lose the digits that make it small on a
/// slender beam ((beta r)^2 E/(kG) of them, 5 at L/h = 2300).
type Values = [f64; 5];

/// The end conditions' quantities: clamped W = Psi = 0, pinned W = Psi' = 0, free Psi' = 0 and
/// shear strain W' - Psi = 0.
fn end_rows(end: End, v: &Values) -> [f64; 2] {
    match end {
        End::Clamped => [v[0], v[2]],
        End::Pinned => [v[0], v[3]],
        End::Free => [v[3], v[4]],
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum End {
    Clamped,
    Pinned,
    Free,
}

fn ends(support: Support) -> (End, End) {
    match support {
        Support::ClampedFree => (End::Clamped, End::Free),
        Support::PinnedPinned => (End::Pinned, End::Pinned),
        Support::ClampedClamped => (End::Clamped, End::Clamped),
        Support::ClampedPinned => (End::Clamped, End::Pinned),
        Support::FreeFree => (End::Free, End::Free),
    }
}

/// cosh(sqrt(s) x) and sinh(sqrt(s) x)/sqrt(s) (cos and sin/k for s = -k^2 < 0), entire in s.
fn entire(s: f64, x: f64) -> (f64, f64) {
    let z = s.abs().sqrt() * x;
    // sinh(z)/z and sin(z)/z by their series below 1e-3 (error z^4/120 < 1e-14).
    let small = z < 1e-3;
    if s >= 0.0 {
        let shc = if small { 1.0 + z * z / 6.0 } else { z.sinh() / z };
        (z.cosh(), x * shc)
    } else {
        let sc = if small { 1.0 - z * z / 6.0 } else { z.sin() / z };
        (z.cos(), x * sc)
    }
}

impl Timoshenko {
    /// rho I / rho A (m^2): the rotary term of the shapes' scaling.
    pub(crate) fn rotary(&self) -> f64 {
        self.rho_i / self.rho_a
    }

    /// Cut-off circular frequency sqrt(kGA / rho I) (rad/s) where the second pair starts to travel.
    pub(crate) fn cutoff(&self) -> f64 {
        (self.kga / self.rho_i).sqrt()
    }

    fn waves(&self, omega: f64) -> Waves {
        let w2 = omega * omega;
        let u = self.rho_i / self.ei + self.rho_a / self.kga;
        let m = self.rho_a / self.ei;
        let c = m * w2 * (w2 * self.rho_i / self.kga - 1.0);
        let b = w2 * u;
        let beta2 = 0.5 * (b + (b * b - 4.0 * c).sqrt());
        // The other root from the product of the roots, free of cancellation.
        let s = -c / beta2;
        let shear = self.rho_a * w2 / self.kga;
        let beta = beta2.sqrt();
        Waves { beta, s, sigma: s + shear, q: (shear - beta2) / beta }
    }

    /// W, W', Psi, Psi', W' - Psi of the four basis functions at x. The shear strain of
    /// e^(lambda x) is (lambda^2 - sigma)/lambda = -(rho A omega^2/kGA)/lambda: -g/beta times
    /// sin(beta x) for cos(beta x) with g = rho A omega^2/kGA, and so on.
    fn basis(&self, w: &Waves, basis: Basis, x: f64) -> [Values; 4] {
        let (sn, cs) = (w.beta * x).sin_cos();
        let (b, q, s, sigma) = (w.beta, w.q, w.s, w.sigma);
        let g = sigma - s;
        let bending = [
            [cs, -b * sn, q * sn, q * b * cs, -g / b * sn],
            [sn, b * cs, -q * cs, q * b * sn, g / b * cs],
        ];
        let second = match basis {
            Basis::Exponential => {
                let alpha = s.sqrt();
                let right = (alpha * (x - self.length)).exp();
                let left = (-alpha * x).exp();
                let r = sigma / alpha;
                [
                    [right, alpha * right, r * right, sigma * right, -g / alpha * right],
                    [left, -alpha * left, -r * left, sigma * left, g / alpha * left],
                ]
            }
            Basis::Entire => {
                let (ch, sh) = entire(s, x);
                [
                    [ch, s * sh, sigma * sh, sigma * ch, -g * sh],
                    [s * sh, s * ch, sigma * ch, sigma * s * sh, -g * ch],
                ]
            }
        };
        [bending[0], bending[1], second[0], second[1]]
    }

    /// The four end conditions applied to the four basis functions, each row scaled to its
    /// largest entry.
    fn conditions(&self, omega: f64, basis: Basis) -> Matrix4<f64> {
        let w = self.waves(omega);
        let (left, right) = ends(self.support);
        let at0 = self.basis(&w, basis, 0.0);
        let at_l = self.basis(&w, basis, self.length);
        let mut m = Matrix4::zeros();
        for j in 0..4 {
            let [r0, r1] = end_rows(left, &at0[j]);
            let [r2, r3] = end_rows(right, &at_l[j]);
            m[(0, j)] = r0;
            m[(1, j)] = r1;
            m[(2, j)] = r2;
            m[(3, j)] = r3;
        }
        for i in 0..4 {
            let largest = m.row(i).amax();
            if largest > 0.0 {
                m.row_mut(i).scale_mut(1.0 / largest);
            }
        }
        m
    }

    /// alpha L of the second pair (0 above the cut-off, where it travels).
    fn alpha_l(&self, omega: f64) -> f64 {
        self.waves(omega).s.max(0.0).sqrt() * self.length
    }

    /// The basis that holds over [lo, hi], if one does (checked at `samples`).
    fn basis_over(&self, samples: &[f64]) -> Option<Basis> {
        let alphas: Vec<f64> = samples.iter().map(|&w| self.alpha_l(w)).collect();
        let all_positive = samples.iter().all(|&w| self.waves(w).s > 0.0);
        let min = alphas.iter().copied().fold(f64::INFINITY, f64::min);
        let max = alphas.iter().copied().fold(0.0, f64::max);
        if all_positive && min >= EXPONENTIAL_FROM {
            Some(Basis::Exponential)
        } else if max <= ENTIRE_UP_TO {
            Some(Basis::Entire)
        } else {
            None
        }
    }

    /// (beta + k) L / pi, k the shear wavenumber above the cut-off: the number of half waves of
    /// both branches that fit the beam, within a few of the count below omega.
    fn asymptotic_count(&self, omega: f64) -> f64 {
        let w = self.waves(omega);
        (w.beta + (-w.s).max(0.0).sqrt()) * self.length / PI
    }

    /// The number of natural frequencies below omega (rigid-body modes included), exactly: the
    /// Wittrick-Williams count J = J0 + s{K} with segments so short that J0 = 0.
    ///
    /// A clamped segment of length l has, with P = int psi'^2, G = int (w' - psi)^2 and
    /// Poincare's inequality int f^2 <= (l/pi)^2 int f'^2 (f = w, psi, zero at both ends),
    /// int rho A w^2 + rho I psi^2 <= (rho I t + 2 rho A t^2) P + 2 rho A t G with t = (l/pi)^2,
    /// so its first omega^2 is at least min(EI/(rho I t + 2 rho A t^2), kGA/(2 rho A t)).
    pub(crate) fn count_below(&self, omega: f64) -> usize {
        if omega <= 0.0 {
            return 0;
        }
        // Past a million modes the count would factor millions of segments at every call: the
        // asymptotic count (beta + k) L / pi is within a few of the exact one there.
        let estimate = self.asymptotic_count(omega);
        if estimate > 1e6 {
            return estimate as usize;
        }
        // Keep omega^2 below the bound with a margin of 1.25.
        let w2 = 1.25 * omega * omega;
        let shear = self.kga / (2.0 * self.rho_a * w2);
        let bending = (-self.rho_i
            + (self.rho_i * self.rho_i + 8.0 * self.rho_a * self.ei / w2).sqrt())
            / (4.0 * self.rho_a);
        let longest = PI * shear.min(bending).sqrt();
        let ratio = self.length / longest;
        // Segments past ten million, or not a number (a beam of a nanometre: its frequencies'
        // squares overflow): the asymptotic count, as for a million modes.
        if !(ratio.is_finite() && ratio <= 1e7) {
            return if estimate.is_finite() { estimate.max(0.0) as usize } else { usize::MAX };
        }
        let segments = ratio.ceil().max(1.0) as usize;
        let stiffness = self.segment_stiffness(omega, self.length / segments as f64);
        let (left, right) = ends(self.support);
        let dofs = 2 * (segments + 1);
        // Whether a dof is held: clamped ends hold both of their node's, pinned ones its
        // displacement.
        let held = |dof: usize| {
            let end = match dof / 2 {
                0 => left,
                node if node == segments => right,
                _ => return false,
            };
            match end {
                End::Clamped => true,
                End::Pinned => dof % 2 == 0,
                End::Free => false,
            }
        };
        // Row i of the assembled matrix's lower band, band[d] = A(i, i - d), d = 0..=3: every
        // segment adds the same 4 x 4 block on the dofs of its two nodes (the segment before
        // node i/2 first, then the one after). A held dof is a decoupled unit row: a positive
        // pivot that changes no count.
        let band_row = |i: usize| -> [f64; 4] {
            let mut row = [0.0; 4];
            if held(i) {
                row[0] = 1.0;
                return row;
            }
            let node = i / 2;
            let before = (node > 0).then(|| i - 2 * (node - 1));
            let after = (node < segments).then_some(i % 2);
            for a in before.into_iter().chain(after) {
                for (d, entry) in row.iter_mut().enumerate().take(a + 1) {
                    *entry += stiffness[(a, a - d)];
                }
            }
            for (d, entry) in row.iter_mut().enumerate().skip(1) {
                if i >= d && held(i - d) {
                    *entry = 0.0;
                }
            }
            row
        };
        // Banded LDL^T without interchanges; the count is the number of negative pivots
        // (Sylvester's law of inertia). Step j needs only the pivots of the three rows before
        // and the factor's rows j..j+3, kept in rings of four (indexed mod 4): no storage that
        // grows with the segments (a count in the thousands of segments had allocated and
        // cleared three arrays of them, on whichever thread searched).
        let mut pivots = [0.0; 4];
        let mut lower = [[0.0; 4]; 4]; // lower[i % 4][d] = L(i, i - d)
        let mut bands = [[0.0; 4]; 4]; // bands[i % 4] = band_row(i)
        for (i, slot) in bands.iter_mut().enumerate().take(dofs.min(4)) {
            *slot = band_row(i);
        }
        let mut negative = 0;
        for j in 0..dofs {
            let mut d = bands[j % 4][0];
            for k in 1..=3.min(j) {
                let l = lower[j % 4][k];
                d -= l * l * pivots[(j - k) % 4];
            }
            if d == 0.0 {
                d = f64::MIN_POSITIVE;
            }
            if d < 0.0 {
                negative += 1;
            }
            pivots[j % 4] = d;
            for i in j + 1..(j + 4).min(dofs) {
                let mut a = bands[i % 4][i - j];
                for k in i.saturating_sub(3)..j {
                    a -= lower[i % 4][i - k] * lower[j % 4][j - k] * pivots[k % 4];
                }
                lower[i % 4][i - j] = a / d;
            }
            // Row j is done: its slots take row j + 4.
            lower[j % 4] = [0.0; 4];
            if j + 4 < dofs {
                bands[j % 4] = band_row(j + 4);
            }
        }
        negative
    }

    /// The exact dynamic stiffness of a segment of length l at omega: end forces
    /// (-Q(0), -M(0), Q(l), M(l)) against end displacements (W(0), Psi(0), W(l), Psi(l)),
    /// Q = kGA (W' - Psi), M = EI Psi'.
    fn segment_stiffness(&self, omega: f64, l: f64) -> Matrix4<f64> {
        let w = self.waves(omega);
        let short = Timoshenko { length: l, ..*self };
        let at0 = short.basis(&w, Basis::Entire, 0.0);
        let at_l = short.basis(&w, Basis::Entire, l);
        let mut d = Matrix4::zeros();
        let mut f = Matrix4::zeros();
        for j in 0..4 {
            let (a, b) = (at0[j], at_l[j]);
            d[(0, j)] = a[0];
            d[(1, j)] = a[2];
            d[(2, j)] = b[0];
            d[(3, j)] = b[2];
            f[(0, j)] = -self.kga * a[4];
            f[(1, j)] = -self.ei * a[3];
            f[(2, j)] = self.kga * b[4];
            f[(3, j)] = self.ei * b[3];
        }
        // The segment has no clamped frequency below omega, so d is invertible.
        let k = f * d.try_inverse().unwrap_or_else(Matrix4::zeros);
        0.5 * (k + k.transpose())
    }

    /// The first `wanted` elastic modes in order of frequency (the rigid-body modes of a
    /// free-free beam, which come before them, are the caller's).
    pub(crate) fn elastic_modes(&self, wanted: usize) -> Result<Vec<crate::Mode>, ModalError> {
        let count = self.support.rigid_modes() + wanted;
        // An upper bound: where the asymptotic count (beta + k) L / pi (k the shear
        // wavenumber above the cut-off) passes the modes asked for, raised until the exact
        // count holds.
        let target = (count + 2) as f64;
        let (mut below, mut hi) = (0.0, 1.0);
        while self.asymptotic_count(hi) < target {
            below = hi;
            hi *= 2.0;
        }
        for _ in 0..60 {
            let mid = 0.5 * (below + hi);
            if self.asymptotic_count(mid) < target {
                below = mid;
            } else {
                hi = mid;
            }
        }
        let mut j_hi = self.count_below(hi);
        let mut raises = 0;
        while j_hi < count {
            hi *= 1.1;
            j_hi = self.count_below(hi);
            raises += 1;
            if raises > 200 {
                return Err(ModalError::RootNotBracketed {
                    mode: count,
                    support: self.support.name(),
                    guess: hi,
                });
            }
        }
        let scale = (self.ei / self.rho_a).sqrt() / (self.length * self.length);
        // Below a thousandth of the first Euler-Bernoulli frequency only the rigid-body modes lie.
        let first = self.support.eigenvalue(1)?;
        let lo = 1e-3 * first * first * scale;
        let j_lo = self.count_below(lo);
        let mut roots = self.slice((lo, hi), (j_lo, j_hi), 0, wanted);
        roots.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The roots that hold the first `wanted` modes, their shapes side by side (each
        // root's on its own: the same as one by one).
        let mut held = 0;
        let needed = roots
            .iter()
            .position(|r| {
                // A root gives at most four shapes (`shapes`), whatever its multiplicity.
                held += r.1.min(4);
                held >= wanted
            })
            .map_or(roots.len(), |k| k + 1);
        let shapes: Vec<Vec<ModeShape>> = roots[..needed]
            .par_iter()
            .map(|&(omega, multiplicity)| self.shapes(omega, multiplicity))
            .collect();
        let mut modes = Vec::with_capacity(wanted);
        for (&(omega, _), shapes) in roots.iter().zip(shapes) {
            for shape in shapes {
                if modes.len() == wanted {
                    break;
                }
                let beta_l = self.waves(omega).beta * self.length;
                modes.push(crate::Mode { beta_l, omega, shape });
            }
        }
        Ok(modes)
    }

    /// Roots in (lo, hi], where the count rises from j_lo to j_hi, as (omega, multiplicity)
    /// in increasing order; `found` roots (with their multiplicities) lie below lo, and none
    /// are looked for once the first `wanted` elastic roots are found.
    fn slice(
        &self,
        (lo, hi): (f64, f64),
        (j_lo, j_hi): (usize, usize),
        found: usize,
        wanted: usize,
    ) -> Vec<(f64, usize)> {
        let n = j_hi.saturating_sub(j_lo);
        if n == 0 || found >= wanted {
            return Vec::new();
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            return vec![(0.5 * (lo + hi), n)];
        }
        let samples = 8 * n + 1;
        let grid: Vec<f64> =
            (0..=samples).map(|k| lo + (hi - lo) * k as f64 / samples as f64).collect();
        let Some(basis) = self.basis_over(&grid) else {
            return self.halves((lo, hi), (j_lo, j_hi), found, wanted);
        };
        let det = |w: f64| self.conditions(w, basis).determinant();
        // The scan and the polish side by side where the slice holds work worth a thread (the
        // paper's tip's 256 roots come in slices of 103, 56, 33, 20 and fewer, each of which had
        // been scanned and polished on one thread); each sample and root is computed alone, so
        // the same bits.
        let wide = n >= SIDE_BY_SIDE;
        let mut points = map_side_by_side(wide, &grid, |&w| (w, det(w)));
        // Two roots closer than the scan leave no sign change but a dip of |det| between
        // samples of one sign: sample the dips more finely, a few times, before counting.
        for _ in 0..6 {
            let changes = points.windows(2).filter(|p| p[0].1 * p[1].1 < 0.0).count();
            if changes == n {
                let brackets: Vec<&[(f64, f64)]> =
                    points.windows(2).filter(|p| p[0].1 * p[1].1 < 0.0).collect();
                return map_side_by_side(wide, &brackets, |p| {
                    (self.polish(p[0].0, p[1].0, p[0].1, p[1].1, basis), 1)
                });
            }
            if changes > n {
                break;
            }
            let dips: Vec<usize> = (1..points.len() - 1)
                .filter(|&k| {
                    let (a, b, c) = (points[k - 1].1, points[k].1, points[k + 1].1);
                    a * b > 0.0 && b * c > 0.0 && b.abs() < a.abs() && b.abs() < c.abs()
                })
                .collect();
            if dips.is_empty() {
                break;
            }
            let mut extra = Vec::new();
            for k in dips {
                let (x0, x1) = (points[k - 1].0, points[k + 1].0);
                extra.extend((1..16).map(|i| x0 + (x1 - x0) * i as f64 / 16.0));
            }
            points.extend(extra.into_iter().map(|w| (w, det(w))));
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            points.dedup_by(|a, b| a.0.total_cmp(&b.0).is_eq());
        }
        self.halves((lo, hi), (j_lo, j_hi), found, wanted)
    }

    /// [`Self::slice`] on the two halves of (lo, hi], side by side where a thread is free
    /// (`rayon::join`): the count says how many roots the lower half holds, so the upper one
    /// knows how many lie below it without waiting (each half's roots are those the serial
    /// search finds, to the bit; the paper's tip's 256 Timoshenko modes took 1.3 ms on one
    /// core).
    fn halves(
        &self,
        (lo, hi): (f64, f64),
        (j_lo, j_hi): (usize, usize),
        found: usize,
        wanted: usize,
    ) -> Vec<(f64, usize)> {
        let mid = 0.5 * (lo + hi);
        let j_mid = self.count_below(mid);
        let below = found + j_mid.saturating_sub(j_lo);
        let lower = || self.slice((lo, mid), (j_lo, j_mid), found, wanted);
        let upper = || self.slice((mid, hi), (j_mid, j_hi), below, wanted);
        // Side by side only where the halves hold work worth a thread (a root's scan and
        // polish are some microseconds).
        let (mut lower, upper) = if j_hi.saturating_sub(j_lo) >= SIDE_BY_SIDE {
            rayon::join(lower, upper)
        } else {
            (lower(), upper())
        };
        lower.extend(upper);
        lower
    }

    /// The root of the determinant in [a, b] where it changes sign, by the Illinois method
    /// (regula falsi that halves the value kept twice in a row), bisecting when it stalls.
    fn polish(&self, mut a: f64, mut b: f64, mut fa: f64, mut fb: f64, basis: Basis) -> f64 {
        let f = |x: f64| self.conditions(x, basis).determinant();
        let mut kept = 0;
        for iteration in 0..200 {
            if (b - a).abs() <= 2.0 * f64::EPSILON * a.abs().max(b.abs()) {
                break;
            }
            let secant = b - fb * (b - a) / (fb - fa);
            let inside = secant > a.min(b) && secant < a.max(b);
            // Bisect every fourth step once the secant has had its chance.
            let c = if inside && (iteration < 40 || iteration % 4 != 0) {
                secant
            } else {
                0.5 * (a + b)
            };
            let fc = f(c);
            if fc == 0.0 {
                return c;
            }
            if fc * fb < 0.0 {
                (a, fa) = (b, fb);
                kept = 0;
            } else {
                kept += 1;
                if kept >= 2 {
                    fa *= 0.5;
                }
            }
            (b, fb) = (c, fc);
        }
        if fa.abs() < fb.abs() {
            a
        } else {
            b
        }
    }

    /// The `multiplicity` mass-orthonormal shapes of a root: the null space of the end
    /// conditions, in the basis that is well conditioned there.
    fn shapes(&self, omega: f64, multiplicity: usize) -> Vec<ModeShape> {
        let basis = if self.waves(omega).s > 0.0 && self.alpha_l(omega) >= EXPONENTIAL_FROM {
            Basis::Exponential
        } else {
            Basis::Entire
        };
        // Columns scaled to unit size too: the second pair's two columns can differ by
        // sigma/k^2 near the cut-off, and the null vector is found to round-off of the scaled one.
        let mut m = self.conditions(omega, basis);
        let columns: Vec<f64> = (0..4)
            .map(|j| match m.column(j).amax() {
                a if a > 0.0 => a,
                _ => 1.0,
            })
            .collect();
        for (j, scale) in columns.iter().enumerate() {
            m.column_mut(j).scale_mut(1.0 / scale);
        }
        let svd = m.svd(false, true);
        let Some(v_t) = svd.v_t else {
            return Vec::new();
        };
        let mut order: Vec<usize> = (0..4).collect();
        order.sort_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]));
        let w = self.waves(omega);
        let rotary = self.rotary();
        let mut shapes: Vec<ModeShape> = Vec::new();
        for &row in order.iter().take(multiplicity.min(4)) {
            let c: Vec<f64> = (0..4).map(|j| v_t[(row, j)] / columns[j]).collect();
            let mut shape = self.shape_of(&w, basis, &c);
            // Gram-Schmidt against the shapes of the same root (a multiple root only).
            for other in &shapes {
                let overlap = shape.wave_inner(other, rotary) / self.length;
                shape = combine(&shape, other, -overlap);
            }
            let norm = (shape.wave_inner(&shape, rotary) / self.length).sqrt();
            shape = shape.scaled(1.0 / norm);
            // A fixed sign: the largest of W at four points positive.
            let probe = [0.0, 0.381_966, 0.618_034, 1.0]
                .map(|f| shape.value(f * self.length))
                .into_iter()
                .fold(0.0, |best: f64, v| if v.abs() > best.abs() { v } else { best });
            if probe < 0.0 {
                shape = shape.scaled(-1.0);
            }
            shapes.push(shape);
        }
        shapes
    }

    /// The shape of coefficients c on the basis, as bounded waves.
    fn shape_of(&self, w: &Waves, basis: Basis, c: &[f64]) -> ModeShape {
        let i = Complex64::new(0.0, 1.0);
        let bending_w = Complex64::new(c[0], -c[1]);
        // Psi of e^(i beta x) is (-i q) times its W.
        let bending =
            Wave { lambda: i * w.beta, anchor: 0.0, w: bending_w, psi: -i * w.q * bending_w };
        // At the cut-off itself alpha = 0 and the cosh wave's Psi = sigma x is no exponential:
        // a root there (the pinned-pinned Psi-only mode) takes alpha L = 1e-6, whose cosh
        // coefficient is zero to round-off anyway.
        let floor = 1e-12 / (self.length * self.length);
        let s = if w.s.abs() < floor { floor.copysign(w.s) } else { w.s };
        let sigma = w.sigma;
        let second = match basis {
            Basis::Exponential => {
                let alpha = s.sqrt();
                let r = sigma / alpha;
                [
                    Wave {
                        lambda: alpha.into(),
                        anchor: self.length,
                        w: c[2].into(),
                        psi: (r * c[2]).into(),
                    },
                    Wave {
                        lambda: (-alpha).into(),
                        anchor: 0.0,
                        w: c[3].into(),
                        psi: (-r * c[3]).into(),
                    },
                ]
            }
            Basis::Entire => {
                // cosh(alpha x) = (e^(alpha x) + e^(-alpha x))/2 with Psi = sigma sinh(alpha x)/alpha;
                // alpha sinh(alpha x) with Psi = sigma cosh(alpha x); alpha = i k above the cut-off.
                let alpha = Complex64::new(s, 0.0).sqrt();
                let r = sigma / alpha;
                let plus_w = 0.5 * c[2] + 0.5 * alpha * c[3];
                let minus_w = 0.5 * c[2] - 0.5 * alpha * c[3];
                let plus_psi = 0.5 * r * c[2] + 0.5 * sigma * c[3];
                let minus_psi = -0.5 * r * c[2] + 0.5 * sigma * c[3];
                [
                    Wave { lambda: alpha, anchor: 0.0, w: plus_w, psi: plus_psi },
                    Wave { lambda: -alpha, anchor: 0.0, w: minus_w, psi: minus_psi },
                ]
            }
        };
        ModeShape::from_waves(w.beta, self.length, &[bending, second[0], second[1]])
    }
}

/// `f` of each item, in order: under rayon when `wide`, else on this thread (a small slice is
/// not worth the pool's hand-over). Each value is computed alone, so the same bits either way.
fn map_side_by_side<T: Sync, U: Send>(
    wide: bool,
    items: &[T],
    f: impl Fn(&T) -> U + Sync + Send,
) -> Vec<U> {
    if wide {
        items.par_iter().map(f).collect()
    } else {
        items.iter().map(f).collect()
    }
}

/// a + factor b, wave by wave (two shapes of one root share their waves).
fn combine(a: &ModeShape, b: &ModeShape, factor: f64) -> ModeShape {
    let waves: Vec<Wave> = a
        .waves()
        .iter()
        .zip(b.waves())
        .map(|(x, y)| Wave { w: x.w + factor * y.w, psi: x.psi + factor * y.psi, ..*x })
        .collect();
    ModeShape::from_waves(a.beta(), a.length(), &waves)
}
