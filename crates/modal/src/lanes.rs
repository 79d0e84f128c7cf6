//! sin, cos and exp of many arguments at once, in plain arithmetic that the compiler turns
//! into vector instructions (a call to the C library a lane cannot be vectorised): for the
//! mode shapes' curvature at a point, a sine, a cosine and an exponential a wave of every mode
//! ([`crate::Curvatures`]).
//!
//! Each is the textbook scheme: the argument reduced by the nearest multiple of pi/2 (sine,
//! cosine) or ln 2 (exponential) in Cody and Waite's split constants, so that the product of
//! the multiple and the first parts is exact, then the Taylor series of the remainder (|r| <=
//! pi/4: the first term left out of the sine's below 1e-19 of it, the cosine's 1e-20; |r| <=
//! ln(2)/2: the exponential's below 4e-18), then the quadrant's signs and swap or the power of
//! two set in the exponent's bits. Separate multiplies and adds (no fused multiply-add), so the
//! results are the same on every processor. Checked against the standard library's to two
//! units of the last place (the tests below).

/// Runs a vector kernel on the processor's vectors as pulp dispatches them, but on x86-64
/// never on AVX-512's eight lanes: x86-64-v3's four (AVX2 and FMA) where the processor has
/// them, else one. The workspace builds pulp with AVX-512 for the beams' element passes
/// (`hht::fast::run_wide`), so `pulp::Arch::new()` would take eight lanes here too, where the
/// propagation's kernels have their vector path for four lanes only and fall back to one
/// (the paper's tip at 256 modes over 5 ms ran 18 % slower on a processor with AVX-512).
#[inline]
pub fn on_four_lanes<W: pulp::WithSimd>(kernel: W) -> W::Output {
    #[cfg(target_arch = "x86_64")]
    {
        if let Some(simd) = pulp::x86::V3::try_new() {
            return pulp::Simd::vectorize(simd, kernel);
        }
        pulp::Simd::vectorize(pulp::Scalar::new(), kernel)
    }
    #[cfg(not(target_arch = "x86_64"))]
    pulp::Arch::new().dispatch(kernel)
}

/// 1.5 2^52: `x + MAGIC - MAGIC` rounds |x| < 2^51 to the nearest integer, and the low bits of
/// `(x + MAGIC).to_bits()` hold that integer (two's complement within 51 bits).
const MAGIC: f64 = 6_755_399_441_055_744.0;
/// pi/2 as P1 + P2 + P3, P1 and P2 of 33 significant bits: k P1 and k P2 are exact for
/// |k| < 2^20.
const PI_OVER_2: [f64; 3] =
    [1.570_796_326_734_125_6, 6.077_100_506_303_966e-11, 2.022_266_248_795_950_6e-21];
/// The largest |x| the reduction keeps to round-off (|k| < 2^20 with a margin); beyond it the
/// standard library's sine and cosine are taken.
pub(crate) const SIN_COS_REACH: f64 = 1.0e6;
/// ln 2 as L1 + L2, L1 of 29 significant bits (k L1 exact for every k an exponent takes).
const LN_2: [f64; 2] = [0.693_147_180_601_954_5, -4.200_915_072_681_084_6e-11];
/// Below this the exponential is subnormal (or zero): 0 is returned.
const EXP_LOWEST: f64 = -708.0;
/// Above this it overflows: infinity is returned.
const EXP_HIGHEST: f64 = 709.7;

/// (sin x, cos x) for |x| <= [`SIN_COS_REACH`], branch-free.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    let k = (x * std::f64::consts::FRAC_2_PI + MAGIC) - MAGIC;
    let quadrant = (k + MAGIC).to_bits() & 3;
    let r = ((x - k * PI_OVER_2[0]) - k * PI_OVER_2[1]) - k * PI_OVER_2[2];
    let r2 = r * r;
    // sin r = r + r^3 (-1/3! + r^2 (1/5! - ...)) to r^17; cos r = 1 - r^2/2 + r^4 (1/4! - ...)
    // to r^18.
    let s = r2 * (1.0 / 355_687_428_096_000.0) - 1.0 / 1_307_674_368_000.0;
    let s = r2 * s + 1.0 / 6_227_020_800.0;
    let s = r2 * s - 1.0 / 39_916_800.0;
    let s = r2 * s + 1.0 / 362_880.0;
    let s = r2 * s - 1.0 / 5040.0;
    let s = r2 * s + 1.0 / 120.0;
    let s = r2 * s - 1.0 / 6.0;
    let sin_r = r + r * r2 * s;
    let c = r2 * (-1.0 / 6_402_373_705_728_000.0) + 1.0 / 20_922_789_888_000.0;
    let c = r2 * c - 1.0 / 87_178_291_200.0;
    let c = r2 * c + 1.0 / 479_001_600.0;
    let c = r2 * c - 1.0 / 3_628_800.0;
    let c = r2 * c + 1.0 / 40_320.0;
    let c = r2 * c - 1.0 / 720.0;
    let c = r2 * c + 1.0 / 24.0;
    let cos_r = (1.0 - 0.5 * r2) + r2 * r2 * c;
    // Quadrant q: sin x = sin r, cos r, -sin r, -cos r and cos x = cos r, -sin r, -cos r, sin r.
    let swap = quadrant & 1 == 1;
    let (a, b) = if swap { (cos_r, sin_r) } else { (sin_r, cos_r) };
    let sin = f64::from_bits(a.to_bits() ^ ((quadrant & 2) << 62));
    let cos = f64::from_bits(b.to_bits() ^ (((quadrant + 1) & 2) << 62));
    (sin, cos)
}

/// e^x, branch-free: 0 below [`EXP_LOWEST`] (where it is below 3.3e-308), infinity above
/// [`EXP_HIGHEST`].
#[inline(always)]
pub(crate) fn exp(x: f64) -> f64 {
    let clamped = x.clamp(EXP_LOWEST, EXP_HIGHEST);
    let k = (clamped * std::f64::consts::LOG2_E + MAGIC) - MAGIC;
    let power = ((k + MAGIC).to_bits().wrapping_sub(MAGIC.to_bits())) as i64;
    let r = (clamped - k * LN_2[0]) - k * LN_2[1];
    let p = r * (1.0 / 6_227_020_800.0) + 1.0 / 479_001_600.0;
    let p = r * p + 1.0 / 39_916_800.0;
    let p = r * p + 1.0 / 3_628_800.0;
    let p = r * p + 1.0 / 362_880.0;
    let p = r * p + 1.0 / 40_320.0;
    let p = r * p + 1.0 / 5040.0;
    let p = r * p + 1.0 / 720.0;
    let p = r * p + 1.0 / 120.0;
    let p = r * p + 1.0 / 24.0;
    let p = r * p + 1.0 / 6.0;
    let p = r * p + 0.5;
    let p = 1.0 + r + r * r * p;
    let two_k = f64::from_bits(((power + 1023) as u64) << 52);
    let value = p * two_k;
    if x < EXP_LOWEST {
        0.0
    } else if x > EXP_HIGHEST {
        f64::INFINITY
    } else {
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between a and b, at the scale of the larger (or of 1 for sine
    /// and cosine, whose values near their zeros are differences of the argument's round-off).
    fn ulps(a: f64, b: f64, floor: f64) -> f64 {
        (a - b).abs() / (a.abs().max(b.abs()).max(floor) * f64::EPSILON)
    }

    #[test]
    #[allow(clippy::float_cmp)] // exact: sin 0 = 0, cos 0 = 1
    fn sine_and_cosine_match_the_standard_library() {
        // 200001 arguments over [-1e4, 1e4] (a mode's wavenumber times a position reaches
        // 6e4 at 20000 modes of the paper's beam), the small ones, and the multiples of pi/2,
        // where the reduction's remainder is smallest: within 2 ulp of 1 (at values near 1,
        // 2 ulp of themselves).
        let mut args: Vec<f64> = (0..=200_000).map(|i| -1e4 + 0.1 * i as f64).collect();
        args.extend((1..=60).map(|k| 0.5_f64.powi(k)));
        args.extend((-2000..=2000).map(|k| k as f64 * std::f64::consts::FRAC_PI_2));
        args.extend([1e5, -3.3e5, 9.9e5]);
        let mut worst = 0.0_f64;
        for &x in &args {
            let (s, c) = sin_cos(x);
            let (es, ec) = x.sin_cos();
            worst = worst.max(ulps(s, es, 1.0)).max(ulps(c, ec, 1.0));
        }
        assert!(worst <= 2.0, "worst {worst} ulp");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }

    #[test]
    #[allow(clippy::float_cmp)] // exact: 1, 0 and infinity
    fn the_exponential_matches_the_standard_library() {
        // Over [-708, 709.7], to 2 ulp of itself; 0 below, infinity above; exactly 1 at 0.
        let mut worst = 0.0_f64;
        for i in 0..=200_000 {
            let x = -708.0 + 1417.7 * i as f64 / 200_000.0;
            worst = worst.max(ulps(exp(x), x.exp(), f64::MIN_POSITIVE));
        }
        for x in [-1e-300, 1e-17, -0.3465, 0.3466, -30.5, 1.0] {
            worst = worst.max(ulps(exp(x), x.exp(), f64::MIN_POSITIVE));
        }
        assert!(worst <= 2.0, "worst {worst} ulp");
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-750.0), 0.0);
        assert_eq!(exp(800.0), f64::INFINITY);
    }
}
