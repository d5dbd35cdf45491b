//! `[model]` of a rod scenario (`RodModelSpec`): the rod's
//! parameters of (6.1) — mass per length ρ, inertia J, stiffnesses C₁ and
//! C₂, unstressed strain e = e₃ — at its material points, from a
//! cross-section and a material ([`rod_parameters`], possibly varying
//! along the rod) or from the raw data `mass_per_length`,
//! `inertia_density`, `shear_stiffness` and `bending_stiffness` (uniform);
//! with the rod's mass and how finely its material points resolve bending.

use std::path::Path;

use nalgebra::{Matrix3, Vector3};
use veselov::models::rod::{
    BENDING_STIFFENING_PER_LOCKING, CrossSection, Material, RodParameters, locking_number, rod_parameters,
    spacing_for_locking,
};

use super::schema::{Along, ROD_MODEL, RodModelSpec};
use crate::error::CliError;
use crate::output::number;
use crate::scenario::{Array, List, key_error, positive_value, shear_from_keys};

/// The bending stiffening from shear locking that a run's advice aims at: 1 %.
pub const BENDING_STIFFENING_ADVISED: f64 = 0.01;

/// Largest number of material points.
const MAX_NODES: usize = 100_000;

/// The keys of a cross-section and a material.
const SECTION_KEYS: [&str; 8] = [
    "radius",
    "width",
    "height",
    "density",
    "young",
    "poisson",
    "shear_modulus",
    "shear_coefficient",
];

/// The keys of the raw rod data, all needed together.
const RAW_KEYS: [&str; 4] = [
    "mass_per_length",
    "inertia_density",
    "shear_stiffness",
    "bending_stiffness",
];

/// The rod's length, its material points and the parameters there.
pub(super) struct RodBody {
    pub length: f64,
    /// The material points s_k = kL/(N − 1).
    pub points: Vec<f64>,
    /// Whether any key is an expression in s.
    pub varying: bool,
    /// The parameters at each material point.
    pub profile: Vec<RodParameters>,
    /// The parameters at s = 0.
    pub parameters: RodParameters,
    pub mass: f64,
    /// The worst shear-locking number and the material points advised for bending.
    pub locking: f64,
    pub nodes_for_bending: usize,
}

/// `[model]`: the parameters at every material point (from a section and a
/// material, or from the raw data), the mass and the resolution of bending.
pub(super) fn body(path: &Path, m: &RodModelSpec) -> Result<RodBody, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    if m.name != ROD_MODEL {
        return Err(key("model.name", format!("expected \"{ROD_MODEL}\", got `{}`", m.name)));
    }
    if !(3..=MAX_NODES).contains(&m.nodes) {
        return Err(key(
            "model.nodes",
            format!("expected 3..={MAX_NODES} material points, got {}", m.nodes),
        ));
    }
    let length = positive_value(path, "model.length", m.length)?;
    let points: Vec<f64> = (0..m.nodes).map(|k| length * k as f64 / (m.nodes - 1) as f64).collect();
    let (profile, varying) = if raw_style(path, m)? {
        (vec![raw_parameters(path, m)?; m.nodes], false)
    } else {
        section_profile(path, m, &points)?
    };
    let parameters = profile[0];
    // Mass by the trapezoidal rule over the material points.
    let spacing = length / (m.nodes - 1) as f64;
    let mass = profile
        .windows(2)
        .map(|w| 0.5 * (w[0].rho() + w[1].rho()) * spacing)
        .sum();
    let locking = profile.iter().map(|q| locking_number(q, spacing)).fold(0.0, f64::max);
    let resolved = profile
        .iter()
        .map(|q| spacing_for_locking(q, BENDING_STIFFENING_ADVISED / BENDING_STIFFENING_PER_LOCKING))
        .fold(f64::INFINITY, f64::min);
    // Saturating: a huge count is advice, not an allocation.
    let nodes_for_bending = (length / resolved).ceil().min(u32::MAX as f64) as usize + 1;
    Ok(RodBody {
        length,
        points,
        varying,
        profile,
        parameters,
        mass,
        locking,
        nodes_for_bending,
    })
}

/// Whether `[model]` gives the raw rod data (a key of [`RAW_KEYS`]) rather
/// than a section and a material; both styles at once are refused, naming
/// the first raw key.
fn raw_style(path: &Path, m: &RodModelSpec) -> Result<bool, CliError> {
    let section = [
        m.radius.is_some(),
        m.width.is_some(),
        m.height.is_some(),
        m.density.is_some(),
        m.young.is_some(),
        m.poisson.is_some(),
        m.shear_modulus.is_some(),
        m.shear_coefficient.is_some(),
    ];
    let raw = raw_given(m);
    let first = |given: &[bool], names: &[&'static str]| names.iter().zip(given).find(|(_, g)| **g).map(|(n, _)| *n);
    match (first(&section, &SECTION_KEYS), first(&raw, &RAW_KEYS)) {
        (Some(s), Some(r)) => Err(key_error(
            path,
            &format!("model.{r}"),
            format!(
                "the raw rod data ({}) replace a cross-section and a material, but `model.{s}` is also given: \
                 give one style, not both",
                RAW_KEYS.join(", ")
            ),
        )),
        (_, raw) => Ok(raw.is_some()),
    }
}

fn raw_given(m: &RodModelSpec) -> [bool; 4] {
    [
        m.mass_per_length.is_some(),
        m.inertia_density.is_some(),
        m.shear_stiffness.is_some(),
        m.bending_stiffness.is_some(),
    ]
}

/// The uniform rod of the raw data: ρ = `mass_per_length`, J =
/// `inertia_density`, C₁ = diag(`shear_stiffness`), C₂ =
/// diag(`bending_stiffness`), e = e₃; each refused, naming the key (and the
/// entry), when missing, not positive, or (J) not symmetric positive
/// definite.
fn raw_parameters(path: &Path, m: &RodModelSpec) -> Result<RodParameters, CliError> {
    if let Some((missing, _)) = RAW_KEYS.iter().zip(raw_given(m)).find(|(_, given)| !given) {
        return Err(key_error(
            path,
            &format!("model.{missing}"),
            format!(
                "missing: the raw rod data need all four of {} (or give a cross-section and a material instead)",
                RAW_KEYS.join(", ")
            ),
        ));
    }
    let rho = positive_value(path, "model.mass_per_length", m.mass_per_length.unwrap_or(f64::NAN))?;
    let inertia = inertia(path, m.inertia_density.as_ref())?;
    let c1 = diagonal(path, "model.shear_stiffness", m.shear_stiffness.as_ref())?;
    let c2 = diagonal(path, "model.bending_stiffness", m.bending_stiffness.as_ref())?;
    RodParameters::new(rho, inertia, c1, c2, Vector3::new(0.0, 0.0, 1.0))
        .map_err(|e| key_error(path, "model", e.to_string()))
}

/// A diagonal stiffness: 3 positive numbers, each named `key[i]` when not.
fn diagonal(path: &Path, key: &str, given: Option<&Array<f64, 3>>) -> Result<Matrix3<f64>, CliError> {
    let Some(given) = given else {
        return Err(key_error(path, key, "missing"));
    };
    let v = given.values(path, key)?;
    let mut d = Vector3::zeros();
    for i in 0..3 {
        d[i] = positive_value(path, &format!("{key}[{i}]"), v[i])?;
    }
    Ok(Matrix3::from_diagonal(&d))
}

/// The largest asymmetry |J_ij − J_ji| accepted, relative to the largest entry.
const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// `model.inertia_density`: the diagonal (3 positive numbers) or the full
/// tensor row by row (9 numbers, symmetric to [`SYMMETRY_TOLERANCE`] and
/// positive definite), symmetrised exactly.
fn inertia(path: &Path, given: Option<&List<f64>>) -> Result<Matrix3<f64>, CliError> {
    const KEY: &str = "model.inertia_density";
    let Some(given) = given else {
        return Err(key_error(path, KEY, "missing"));
    };
    let v = given.values(
        path,
        KEY,
        &[3, 9],
        " (the diagonal I₁, I₂, I₃, or the tensor's entries row by row)",
    )?;
    if v.len() == 3 {
        let mut d = Vector3::zeros();
        for i in 0..3 {
            d[i] = positive_value(path, &format!("{KEY}[{i}]"), v[i])?;
        }
        return Ok(Matrix3::from_diagonal(&d));
    }
    let j = Matrix3::from_row_slice(&v);
    let scale = j.amax();
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        if (j[(a, b)] - j[(b, a)]).abs() > SYMMETRY_TOLERANCE * scale {
            return Err(key_error(
                path,
                &format!("{KEY}[{}]", 3 * b + a),
                format!(
                    "J[{b}][{a}] = {} but J[{a}][{b}] = {}: the tensor must be symmetric",
                    number(j[(b, a)]),
                    number(j[(a, b)])
                ),
            ));
        }
    }
    for a in 0..3 {
        if j[(a, a)] <= 0.0 || !j[(a, a)].is_normal() {
            return Err(key_error(
                path,
                &format!("{KEY}[{}]", 4 * a),
                format!(
                    "the diagonal entry J[{a}][{a}] = {} must be positive",
                    number(j[(a, a)])
                ),
            ));
        }
    }
    let j = (j + j.transpose()) * 0.5;
    let eigenvalues = j.symmetric_eigenvalues();
    if j.cholesky().is_none() || eigenvalues.min() <= 0.0 {
        let mut e: Vec<f64> = eigenvalues.iter().copied().collect();
        e.sort_by(f64::total_cmp);
        return Err(key_error(
            path,
            KEY,
            format!(
                "the tensor must be positive definite; its eigenvalues are {}, {} and {}",
                number(e[0]),
                number(e[1]),
                number(e[2])
            ),
        ));
    }
    Ok(j)
}

/// The parameters at the material points `points` from a cross-section and a
/// material (each key a number or an expression in s, evaluated there), and
/// whether any of them varies.
fn section_profile(path: &Path, m: &RodModelSpec, points: &[f64]) -> Result<(Vec<RodParameters>, bool), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let varying = [&m.radius, &m.width, &m.height, &m.density, &m.young]
        .into_iter()
        .flatten()
        .any(|v| matches!(v, Along::Expression(_)));
    let along = |k: &str, v: &Along| v.at(path, k, points);
    let needed = |k: &str, v: &Option<Along>| match v {
        Some(v) => along(k, v),
        None => Err(key(
            k,
            format!(
                "missing: a cross-section needs `density` and `young` (or give the raw rod data {} instead)",
                RAW_KEYS.join(", ")
            ),
        )),
    };
    let sections: Vec<CrossSection> = match (&m.radius, &m.width, &m.height) {
        (Some(r), None, None) => along("model.radius", r)?
            .into_iter()
            .map(|radius| CrossSection::Circle { radius })
            .collect(),
        (None, Some(w), Some(h)) => along("model.width", w)?
            .into_iter()
            .zip(along("model.height", h)?)
            .map(|(width, height)| CrossSection::Rectangle { width, height })
            .collect(),
        _ => {
            return Err(key(
                "model.radius",
                format!(
                    "give the cross-section as `radius` (circle) or `width` and `height` (rectangle), or the \
                     raw rod data ({})",
                    RAW_KEYS.join(", ")
                ),
            ));
        }
    };
    let (densities, youngs) = (needed("model.density", &m.density)?, needed("model.young", &m.young)?);
    let shear = shear_from_keys(path, m.poisson, m.shear_modulus)?;
    let given_kappa = match m.shear_coefficient {
        Some(k) => Some(positive_value(path, "model.shear_coefficient", k)?),
        None => None,
    };
    let profile = (0..points.len())
        .map(|k| {
            let young = youngs[k];
            let kappa = given_kappa.unwrap_or_else(|| sections[k].cowper_shear_coefficient(shear.poisson_ratio(young)));
            let material = Material {
                density: densities[k],
                young,
                shear,
                shear_coefficient: kappa,
            };
            rod_parameters(&sections[k], &material).map_err(|e| key("model", format!("at s = {}: {e}", points[k])))
        })
        .collect::<Result<Vec<RodParameters>, CliError>>()?;
    Ok((profile, varying))
}
