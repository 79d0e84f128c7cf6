//! Hot loops compiled for the processor's vector instructions, chosen at run time.
//!
//! The crates build for the baseline x86-64 (SSE2, no fused multiply-add), so that a binary
//! runs on any x86-64. A [`Kernel`] is compiled a second time for x86-64-v3 (AVX2 and FMA),
//! through pulp's run-time dispatch, and that copy runs where the processor has it: four
//! lanes instead of two in the loops the compiler vectorises, and one rounding and one
//! latency instead of two in a multiply-add ([`MulAdd`]), which is what bounds a triangular
//! solve's chain from one unknown to the next. Elsewhere the baseline copy runs, with the
//! separate multiply and add. The two copies give the same results to rounding.

/// `a b + c`, fused (one rounding) or not, as the kernel's copy was compiled.
pub trait MulAdd: Copy {
    /// `a b + c`.
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64;
}

/// The fused multiply-add of a processor that has one.
#[derive(Debug, Clone, Copy)]
pub struct Fused;

/// A multiply, then an add (the baseline; `f64::mul_add` would call a library routine).
#[derive(Debug, Clone, Copy)]
pub struct Separate;

impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

impl MulAdd for Separate {
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

/// A loop to compile twice. `run` must be `#[inline(always)]` (and what it calls in the loop
/// too), so that its body lands in the copy compiled with the wider instructions.
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// The loop, with `arith` for its multiply-adds.
    fn run<A: MulAdd>(self, arith: A) -> Self::Output;
}

/// Runs `kernel` in its x86-64-v3 copy where the processor has AVX2 and FMA, else in the
/// baseline copy.
#[inline]
pub fn run<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(simd) = pulp::x86::V3::try_new() {
        return pulp::Simd::vectorize(simd, WithFma(kernel));
    }
    kernel.run(Separate)
}

/// Runs `f` as [`run`] runs a kernel: a loop without multiply-adds of its own, for the wider
/// lanes only (the closure is inlined into each copy).
#[inline]
pub fn wide<R>(f: impl FnOnce() -> R) -> R {
    run(Closure(f))
}

struct Closure<F>(F);

impl<R, F: FnOnce() -> R> Kernel for Closure<F> {
    type Output = R;

    #[inline(always)]
    fn run<A: MulAdd>(self, _: A) -> R {
        (self.0)()
    }
}

/// `x . y`, in four partial sums (one chain of additions would bound it by their latency).
#[inline(always)]
pub(crate) fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    let (xs, ys) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xs.remainder().iter().zip(ys.remainder()).map(|(a, b)| a * b).sum();
    for (a, b) in xs.zip(ys) {
        for k in 0..4 {
            sums[k] += a[k] * b[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

struct WithFma<K>(K);

impl<K: Kernel> pulp::WithSimd for WithFma<K> {
    type Output = K::Output;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> K::Output {
        self.0.run(Fused)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Dot<'a>(&'a [f64], &'a [f64]);

    impl Kernel for Dot<'_> {
        type Output = f64;
        #[inline(always)]
        fn run<A: MulAdd>(self, arith: A) -> f64 {
            self.0.iter().zip(self.1).fold(0.0, |s, (a, b)| arith.mul_add(*a, *b, s))
        }
    }

    #[test]
    fn both_copies_compute_the_same_sum() {
        // Exact in either rounding: small integers.
        let (x, y): (Vec<f64>, Vec<f64>) = (0..100).map(|i| (i as f64, (i % 7) as f64)).unzip();
        let exact: f64 = (0..100).map(|i| (i * (i % 7)) as f64).sum();
        assert_eq!(run(Dot(&x, &y)).to_bits(), exact.to_bits());
        assert_eq!(Dot(&x, &y).run(Separate).to_bits(), exact.to_bits());
        assert_eq!(Dot(&x, &y).run(Fused).to_bits(), exact.to_bits());
    }
}
