//! TEMPORARY placeholder (libm-based) until the vectorizable implementation lands.

#[inline(always)]
pub fn pow_unit_f64(x: f64, one_minus_x: f64, p: f64) -> f64 {
    if p == 0.0 {
        1.0
    } else if x >= 0.5 {
        (p * (-one_minus_x).ln_1p()).exp()
    } else {
        x.powf(p)
    }
}
#[inline(always)]
pub fn pow_unit_f32(x: f32, one_minus_x: f32, p: f32) -> f32 {
    pow_unit_f64(x as f64, one_minus_x as f64, p as f64) as f32
}
#[inline(always)]
pub fn exp_f64(x: f64) -> f64 {
    x.exp()
}
#[inline(always)]
pub fn exp_f32(x: f32) -> f32 {
    x.exp()
}
#[inline(always)]
pub fn log_f64(x: f64) -> f64 {
    x.ln()
}
#[inline(always)]
pub fn log_f32(x: f32) -> f32 {
    x.ln()
}
