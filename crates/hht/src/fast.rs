//! Hot loops compiled for the processor's vector instructions, chosen at run time.
//!
//! The crates build for the baseline x86-64 (SSE2, no fused multiply-add), so that a binary
//! runs on any x86-64. A [`Kernel`] is compiled a second time for x86-64-v3 (AVX2 and FMA),
//! through pulp's run-time dispatch, and that copy runs where the processor has it: four
//! lanes instead of two in the loops the compiler vectorises, and one rounding and one
//! latency instead of two in a multiply-add ([`MulAdd`]), which is what bounds a triangular
//! solve's chain from one unknown to the next. Elsewhere the baseline copy runs, with the
//! separate multiply and add. The two copies give the same results to rounding. A few kernels
//! ([`run_wide`]) have a third copy, for AVX-512, that gives the v3 copy's bits.

/// pulp's vector interface and its one-lane machine, for [`Lanes`] kernels outside this crate.
pub use pulp::{Scalar, Simd};

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
/// too), so that its body lands in the copy compiled with the wider instructions. A struct
/// holding the loop's data, not a closure: a closure's body is a function of its own that the
/// compiler did not inline into the wider copy (three planar kernels run through one went
/// 1.6-2.3x slower).
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

/// [`run`], in a third copy compiled for x86-64-v4 (AVX-512: eight lanes, 32 vector
/// registers) where the processor has it. For the loops whose iteration is a long chain of
/// dependent products (the beams' element force passes): eight lanes in one register carry
/// two chains of four at once (on an AMD EPYC, criterion, the passes at 256 elements 0.82 ->
/// 0.68 us in the plane and 3.84 -> 3.60 us in 3D; the paper's tip 2 % faster in either),
/// by the same operations lane by lane, so the same bits; with the 3D pass's scatter summed
/// on the lanes, 2.93 us in 3D, where the four lanes' copy gained nothing from that. Not for
/// every loop: the modal propagation on eight lanes ran 18 % slower (`modal::on_four_lanes`
/// keeps it on four), the 3D beam's configuration update 1 %, and the banded solve and the 3D
/// inertial force gained nothing.
///
/// This crate builds pulp with its `x86-v4` feature, which Cargo turns on for every user of
/// pulp in the build: faer too then dispatches its kernels to AVX-512 where the processor
/// has it (its sparse LU, dense eigen-solver and products). Measured against the build
/// without the feature on such a processor: the same results to the bit on the validation
/// scenes that reach faer (a frame's fe and modal runs, a beam scene's statics) and on the
/// paper's tip, and no run slower (the frame's fe run 9 % faster).
#[inline]
pub fn run_wide<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(simd) = pulp::x86::V4::try_new() {
        return pulp::Simd::vectorize(simd, WithFma(kernel));
    }
    run(kernel)
}

/// Whether [`run_wide`] runs its own copy here (the processor has AVX-512): the tests that
/// hold it to [`run`]'s bits have nothing to compare without.
pub fn wide_lanes() -> bool {
    #[cfg(target_arch = "x86_64")]
    return pulp::x86::V4::try_new().is_some();
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// `x . y`, in four partial sums (one chain of additions would bound it by their latency),
/// in a fixed order: the same result on every processor.
#[inline(always)]
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
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

/// The largest |x_i| (0 for none; a NaN is never taken), in four partial maxima as
/// [`dot`]'s sums: one chain of comparisons would bound it by their latency.
#[inline(always)]
pub fn largest_magnitude(x: &[f64]) -> f64 {
    let larger = |m: f64, v: f64| if v.abs() > m { v.abs() } else { m };
    let mut most = [0.0; 4];
    let chunks = x.chunks_exact(4);
    let tail = chunks.remainder().iter().fold(0.0, |m, v| larger(m, *v));
    for c in chunks {
        for k in 0..4 {
            most[k] = larger(most[k], c[k]);
        }
    }
    most.into_iter().fold(tail, larger)
}

/// A loop written on the processor's vectors (pulp's [`pulp::Simd`]): for the loops the
/// compiler leaves scalar when asked to vectorise them itself (a sweep that writes one
/// vector and sums squares of others, measured 0.6 us for 773 entries, against 0.3 us on
/// four-lane vectors). `run` must be `#[inline(always)]`; [`run_lanes`] calls it with x86-64-v3's
/// four lanes where the processor has them, else with one (its multiply-adds then separate,
/// as [`Separate`]'s).
pub trait Lanes {
    /// What the kernel returns.
    type Output;
    /// The loop, on `simd`'s vectors (see [`whole`] for the part they fill).
    fn run<S: pulp::Simd>(self, simd: S) -> Self::Output;
}

/// Runs `kernel` on four-lane vectors where the processor has AVX2 and FMA, else on one lane.
#[inline]
pub fn run_lanes<K: Lanes>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(simd) = pulp::x86::V3::try_new() {
        return pulp::Simd::vectorize(simd, InLanes(kernel));
    }
    kernel.run(pulp::Scalar::new())
}

/// The length of the longest prefix of `len` entries that fills whole vectors of `S`: a
/// [`Lanes`] kernel runs its vector body on it and the same body on one lane
/// (`pulp::Scalar`) on the rest.
#[inline(always)]
pub fn whole<S: pulp::Simd>(len: usize) -> usize {
    len - len % S::F64_LANES
}

struct InLanes<K>(K);

impl<K: Lanes> pulp::WithSimd for InLanes<K> {
    type Output = K::Output;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> K::Output {
        self.0.run(simd)
    }
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

    /// `y = 2 x + y` and `sum x^2`, on whole vectors then one lane for the rest.
    struct Sweep<'a>(&'a [f64], &'a mut [f64]);

    impl Lanes for Sweep<'_> {
        type Output = f64;
        #[inline(always)]
        fn run<S: pulp::Simd>(self, simd: S) -> f64 {
            #[inline(always)]
            fn body<S: pulp::Simd>(simd: S, x: &[f64], y: &mut [f64]) -> f64 {
                let (x, y) = (S::as_simd_f64s(x).0, S::as_mut_simd_f64s(y).0);
                let (two, mut sum) = (simd.splat_f64s(2.0), simd.splat_f64s(0.0));
                for (x, y) in x.iter().zip(y) {
                    *y = simd.mul_add_e_f64s(two, *x, *y);
                    sum = simd.mul_add_e_f64s(*x, *x, sum);
                }
                simd.reduce_sum_f64s(sum)
            }
            let m = whole::<S>(self.0.len());
            let ((x0, x1), (y0, y1)) = (self.0.split_at(m), self.1.split_at_mut(m));
            body(simd, x0, y0) + body(pulp::Scalar::new(), x1, y1)
        }
    }

    #[test]
    fn a_lanes_kernel_covers_every_entry_at_any_length() {
        // Lengths around the vector width: every entry written once, every square summed
        // once (exact: small integers), in the wide copy and the one-lane copy.
        for n in 0..12 {
            let x: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
            let squares: f64 = x.iter().map(|v| v * v).sum();
            for wide in [true, false] {
                let mut y = vec![1.0; n];
                let sum = if wide {
                    run_lanes(Sweep(&x, &mut y))
                } else {
                    Sweep(&x, &mut y).run(pulp::Scalar::new())
                };
                assert!((sum - squares).abs() <= 0.0, "n {n}: {sum} against {squares}");
                let exact = y.iter().zip(&x).all(|(y, x)| y.to_bits() == (2.0 * x + 1.0).to_bits());
                assert!(exact, "n {n}: {y:?}");
            }
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
