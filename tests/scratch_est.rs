use glam::Vec3;
use multirate::analysis::oracle::true_error;
use multirate::analysis::tessellator::triangle_pattern;
use multirate::scene::{Light, MaterialKind};
use multirate::shading::estimator::*;

fn show(name: &str, tri: &TriangleInput, m: &MaterialKind, lights: &[Light]) {
    for eps in [0.1f32, 0.01, 0.001] {
        let s = EstimatorSettings { epsilon: eps, n_max: 64, ..Default::default() };
        let e = estimate(tri, m, lights, &s);
        if e.fallback { println!("{name} eps {eps}: fallback {:?}", e.reason); continue; }
        let p = triangle_pattern(e.n as f32, [e.n as f32; 3]);
        let t = true_error(tri, m, lights, &p);
        let tw = t.iter().cloned().fold(0.0, f64::max);
        let terms: Vec<String> = e.named_terms().filter(|(_, v)| *v > 0.0).map(|(k, v)| format!("{k}={v:.2}")).collect();
        // oracle level
        let mut lvl = 0; for n in 1..=64 { let p = triangle_pattern(n as f32, [n as f32;3]); let t = true_error(tri, m, lights, &p); if t.iter().all(|&x| x <= eps as f64) { lvl = n; break; } }
        println!("{name} eps {eps}: n {} oracle {} pred {:.3e} true {:.3e} ratio {:.2} | {}", e.n, lvl, e.predicted_error, tw, e.predicted_error as f64 / tw, terms.join(" "));
    }
}

#[test]
fn scratch() {
    let eq = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.5, 0.866, 0.0)];
    let up = Vec3::Z;
    let lam = MaterialKind::Lambert { kd: Vec3::ONE };
    // A: point light above centroid
    for h in [0.3f32, 1.0, 3.0] {
        let tri = TriangleInput { positions: eq, normals: [up; 3], eye: Vec3::new(0.5, 0.3, 5.0) };
        let l = [Light::Point { position: Vec3::new(0.5, 0.29, h), color: Vec3::ONE, intensity: h * h }];
        show(&format!("A h={h}"), &tri, &lam, &l);
    }
    // B: directional, normal spread
    for sp in [0.05f32, 0.2, 0.5] {
        let ns = [Vec3::new(-sp, -sp, 1.0).normalize(), Vec3::new(sp, -sp, 1.0).normalize(), Vec3::new(0.0, sp, 1.0).normalize()];
        let tri = TriangleInput { positions: eq, normals: ns, eye: Vec3::new(0.5, 0.3, 5.0) };
        for ang in [0.0f32, 0.7] {
            let l = [Light::Directional { direction: -Vec3::new(ang.sin(), 0.0, ang.cos()), color: Vec3::ONE, intensity: 1.0 }];
            show(&format!("B sp={sp} ang={ang}"), &tri, &lam, &l);
            let bp = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 50.0 };
            show(&format!("BP sp={sp} ang={ang}"), &tri, &bp, &l);
            let gg = MaterialKind::Ggx { albedo: Vec3::ZERO, f0: Vec3::splat(0.04), roughness: 0.4 };
            show(&format!("GGX sp={sp} ang={ang}"), &tri, &gg, &l);
        }
    }
}
