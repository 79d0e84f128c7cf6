//! The Illinois variant of regula falsi (Dowell & Jarratt 1971), shared by both solvers to
//! locate contact onset and separation in time.

/// A bracket [a, b] of a sign change of f, narrowed by [`Illinois::narrow`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Illinois {
    /// Left end and f there.
    pub a: f64,
    fa: f64,
    /// Right end and f there.
    pub b: f64,
    fb: f64,
    /// Which end moved last: -1 left, 1 right, 0 none yet.
    side: i8,
}

impl Illinois {
    /// The bracket [a, b] with f(a) = fa and f(b) = fb of opposite signs.
    pub fn new(a: f64, fa: f64, b: f64, fb: f64) -> Self {
        Self { a, fa, b, fb, side: 0 }
    }

    /// The next trial point (secant through the ends), or `None` once it no longer falls
    /// strictly inside the bracket (the bracket is as narrow as round-off allows).
    pub fn trial(&self) -> Option<f64> {
        let c = (self.a * self.fb - self.b * self.fa) / (self.fb - self.fa);
        (c > self.a && c < self.b).then_some(c)
    }

    /// Replaces the end on the side of f(c) = fc; when the same end moves twice in a row the
    /// other end's value is halved, which keeps the convergence superlinear where plain
    /// regula falsi would stall with one end fixed.
    pub fn narrow(&mut self, c: f64, fc: f64) {
        if (fc > 0.0) == (self.fa > 0.0) {
            self.a = c;
            self.fa = fc;
            if self.side == -1 {
                self.fb *= 0.5;
            }
            self.side = -1;
        } else {
            self.b = c;
            self.fb = fc;
            if self.side == 1 {
                self.fa *= 0.5;
            }
            self.side = 1;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::Illinois;

    #[test]
    fn finds_the_root_of_a_convex_function_superlinearly() {
        // f(x) = x^3 - 2 on [0, 2]: plain regula falsi keeps the right end and needs ~100
        // iterations for 1e-12; Illinois needs well under 20.
        let f = |x: f64| x * x * x - 2.0;
        let mut bracket = Illinois::new(0.0, f(0.0), 2.0, f(2.0));
        let mut iterations = 0;
        while let Some(c) = bracket.trial() {
            let fc = f(c);
            iterations += 1;
            if fc.abs() < 1e-12 {
                assert!((c - 2f64.cbrt()).abs() < 1e-12);
                break;
            }
            bracket.narrow(c, fc);
        }
        assert!(iterations < 20, "{iterations} iterations");
    }
}
