//! One colour per integrator, for everything that draws them: bodies, trails and the legend in
//! the window, the lines of the study's work-precision plot (and the window's plots).
//!
//! Chosen to read on the window's dark background and on the plot's white one: mid-lightness
//! hues, and a neutral grey (not white or black) for the exact solution.

use crate::integrate::Integrator;

/// RGBA, 8 bits a channel.
pub type Rgba = [u8; 4];

/// The colour `integrator` is drawn in, everywhere.
pub fn integrator(integrator: Integrator) -> Rgba {
    match integrator {
        Integrator::ExplicitEuler => [235, 85, 75, 255],
        Integrator::SemiImplicitEuler => [245, 170, 50, 255],
        Integrator::VelocityVerlet => [90, 200, 100, 255],
        Integrator::Midpoint => [180, 120, 230, 255],
        Integrator::Rk4 => [80, 160, 245, 255],
        Integrator::ImplicitEuler => [60, 205, 200, 255],
        Integrator::Exact => [160, 160, 160, 255],
        Integrator::ForestRuth => [230, 110, 180, 255],
        Integrator::Dopri5 => [150, 190, 60, 255],
        Integrator::ImplicitMidpoint => [210, 150, 110, 255],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every integrator gets its own colour, and each differs enough from white (the plot) and
    /// from near-black (the window) to be seen on both.
    #[test]
    fn colours_are_distinct_and_visible_on_light_and_dark() {
        let all = Integrator::ALL;
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert_ne!(integrator(*a), integrator(*b), "{a} and {b}");
            }
            let c = integrator(*a);
            let luma =
                (299 * u32::from(c[0]) + 587 * u32::from(c[1]) + 114 * u32::from(c[2])) / 1000;
            assert!((60..=200).contains(&luma), "{a}: luma {luma}");
        }
    }
}
