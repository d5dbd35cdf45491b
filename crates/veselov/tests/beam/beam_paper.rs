//! Seed 000 §5: the prescribed first two columns and their strains (Fig. 3)
//! from the stated data, against the matrix Cayley map
//! (I − x̂/2)⁻¹(I + x̂/2) and its inverse x̂ = 2(G − I)(G + I)⁻¹ evaluated on
//! 4 × 4 matrices (independent of the closed forms in `lie::se3`), and the
//! closed-form motion of the root (rotation about E2, translation along E2).

use nalgebra::{Matrix4, SVector};
use veselov::lie::{CayleyMap, SE3, se3};
use veselov::models::beam::paper::{DS, DT, LAST_TIME_NODE, XI0, XI1, prescribed_columns, root_strains};

fn matrix_cayley(x: &SVector<f64, 6>) -> Matrix4<f64> {
    let h = se3::hat(x) * 0.5;
    (Matrix4::identity() - h).try_inverse().expect("invertible") * (Matrix4::identity() + h)
}

fn matrix_cayley_inv(g: &Matrix4<f64>) -> SVector<f64, 6> {
    let i = Matrix4::identity();
    se3::vee(&((g - i) * (g + i).try_inverse().expect("angle below π") * 2.0))
}

#[test]
fn prescribed_columns_and_root_strains() {
    let last = LAST_TIME_NODE + 1;
    let (c0, c1) = prescribed_columns::<CayleyMap>(last);
    assert_eq!((c0.len(), c1.len()), (last + 1, last + 1));
    let (s0, s1) = (
        matrix_cayley(&(SVector::from(XI0) * DT)),
        matrix_cayley(&(SVector::from(XI1) * DT)),
    );
    let mut m0 = Matrix4::identity();
    let mut m1 = SE3::from_translation(nalgebra::Vector3::new(0.0, 0.0, DS)).to_matrix();
    let strains = root_strains::<CayleyMap>(&c0, &c1).expect("below the cut locus");
    // Root: angle per step 2 atan(|ω|Δt/2) about E2; translation along E2,
    // r_1 = 2/(4 + n²)(2 + n²/2)(−0.1Δt), n = 0.85Δt (note 000 §13, ω ∥ v).
    let n2 = (0.85 * DT) * (0.85 * DT);
    let r1 = 2.0 / (4.0 + n2) * (2.0 + n2 / 2.0) * (-0.1 * DT);
    let angle = 2.0 * (0.85 * DT / 2.0).atan();
    for j in 0..=last {
        assert!((c0[j].to_matrix() - m0).amax() <= 1e-13, "g_0^{j}");
        assert!((c1[j].to_matrix() - m1).amax() <= 1e-13, "g_1^{j}");
        let eta = matrix_cayley_inv(&(m0.try_inverse().expect("rigid") * m1)) / DS;
        assert!(
            (strains[j] - eta).amax() <= 1e-10 * (1.0 + eta.amax()),
            "η_0^{j}: {} vs {eta}",
            strains[j]
        );
        let t = c0[j].translation();
        assert!(
            t[0].abs() + t[2].abs() <= 1e-15 && (t[1] - j as f64 * r1).abs() <= 1e-14,
            "root translation {j}"
        );
        let rot = c0[j].rotation().matrix();
        let a = j as f64 * angle;
        assert!((rot[(0, 0)] - a.cos()).abs() <= 1e-13 && (rot[(2, 0)] + (-a).sin()).abs() <= 1e-13 || j == 0);
        m0 *= s0;
        m1 *= s1;
    }
    // η_0^0 = E6: the beam starts straight and unstretched.
    let e6 = SVector::<f64, 6>::from([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    assert!((strains[0] - e6).amax() <= 1e-14);
    // Fig. 3: the root frames g_0^j, j = 0..3.
    for (j, g) in c0.iter().enumerate().take(4) {
        eprintln!(
            "g_0^{j}: R = {:?}, r = {:?}",
            g.rotation().matrix().as_slice(),
            g.translation().as_slice()
        );
    }
    eprintln!("η_0^{}: {:?}", LAST_TIME_NODE, strains[LAST_TIME_NODE].as_slice());
}
