//! The sample rod and motion that several rod tests share.

use nalgebra::Vector3;
use veselov::field::fibre::Pose;
use veselov::lie::so3;
use veselov::models::rod::RodParameters;
use veselov::models::rod::{CrossSection, Material, Shear, rod_parameters};

/// A slender steel-like rod of circular cross-section `radius` in units
/// with E/ρ = 1 (fastest wave speed 1): ρ = 1, E = 1, Poisson ratio 0.3,
/// shear coefficient 0.9.
pub fn unit_rod(radius: f64) -> RodParameters {
    let material = Material {
        density: 1.0,
        young: 1.0,
        shear: Shear::Poisson(0.3),
        shear_coefficient: 0.9,
    };
    rod_parameters(&CrossSection::Circle { radius }, &material).expect("valid rod")
}

/// A tumbling, vibrating motion of a rod of `length`: slightly bent along
/// e₃, spinning about an oblique axis and translating, with a bending wave.
pub fn tumbling(length: f64) -> impl Fn(f64, f64) -> Pose<f64> {
    move |s, t| {
        let k = std::f64::consts::PI / length;
        let spin = so3::exp(&(Vector3::new(0.3, -0.2, 0.5) * t));
        let bend = 0.05 * (k * s).sin() * (1.0 + 0.5 * (3.0 * t).cos());
        let slope = 0.05 * k * (k * s).cos() * (1.0 + 0.5 * (3.0 * t).cos());
        let local = Vector3::new(bend, 0.02 * (2.0 * k * s).sin() * t, s * (1.0 + 0.01 * t));
        let frame = spin.compose(&so3::exp(&Vector3::new(0.0, slope, 0.1 * s * t)));
        Pose::new(spin.act(&local) + Vector3::new(0.1, 0.2, -0.3) * t, frame)
    }
}
