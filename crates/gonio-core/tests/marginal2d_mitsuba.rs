//! `gonio_core::marginal2d::Marginal2D` against Mitsuba 3.9.1's `MarginalContinuous2D0/2/3`
//! (`testdata/measured/marginal2d-values.json`, made by `testdata/measured/make_reference.py`):
//! seven small tables, normalized or not, with 0, 2 or 3 parameters (uneven nodes, a one-node
//! axis), a zero column and constant segments; eval, sample and invert at ten points each, the
//! parameters on nodes, between them and beyond the ends. The warp is what indexes an RGL
//! table, so it must be Mitsuba's map, not just one with the same density.

use glam::Vec2;
use gonio_core::marginal2d::Marginal2D;
use serde_json::Value;

fn f32s(v: &Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

fn vec2(v: &Value) -> Vec2 {
    let a = f32s(v);
    Vec2::new(a[0], a[1])
}

/// |got − want| relative to max(|want|, 1) (densities and unit-square coordinates are O(1)).
fn close(got: f32, want: f64, tol: f64) -> bool {
    (got as f64 - want).abs() <= tol * want.abs().max(1.0)
}

#[test]
fn marginal2d_matches_mitsubas_continuous_warp() {
    let data: Value =
        serde_json::from_str(include_str!("../../../testdata/measured/marginal2d-values.json")).unwrap();
    let mut checked = 0;
    for t in data["tables"].as_array().unwrap() {
        let name = t["name"].as_str().unwrap();
        let size = f32s(&t["size"]);
        let params: Vec<Vec<f32>> = t["param_values"].as_array().unwrap().iter().map(f32s).collect();
        let m = Marginal2D::new(
            [size[0] as usize, size[1] as usize],
            params,
            &f32s(&t["data"]),
            t["normalize"].as_bool().unwrap(),
            true,
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        for q in t["eval"].as_array().unwrap() {
            let (p, param) = (vec2(&q["pos"]), f32s(&q["param"]));
            let (got, want) = (m.eval(p, &param), q["value"].as_f64().unwrap());
            assert!(
                close(got, want, 2e-6),
                "{name} eval {p} {param:?}: {got} vs Mitsuba {want}"
            );
            checked += 1;
        }
        for q in t["sample"].as_array().unwrap() {
            let (u, param) = (vec2(&q["u"]), f32s(&q["param"]));
            let (p, pdf) = m.sample(u, &param).unwrap();
            let (wp, wpdf) = (f32s(&q["point"]), q["pdf"].as_f64().unwrap());
            assert!(
                close(p.x, wp[0] as f64, 1e-5) && close(p.y, wp[1] as f64, 1e-5) && close(pdf, wpdf, 1e-5),
                "{name} sample {u} {param:?}: ({p}, {pdf}) vs Mitsuba ({wp:?}, {wpdf})"
            );
            checked += 1;
        }
        for q in t["invert"].as_array().unwrap() {
            let (p, param) = (vec2(&q["point"]), f32s(&q["param"]));
            let (u, pdf) = m.invert(p, &param).unwrap();
            let (wu, wpdf) = (f32s(&q["u"]), q["pdf"].as_f64().unwrap());
            assert!(
                close(u.x, wu[0] as f64, 1e-5) && close(u.y, wu[1] as f64, 1e-5) && close(pdf, wpdf, 1e-5),
                "{name} invert {p} {param:?}: ({u}, {pdf}) vs Mitsuba ({wu:?}, {wpdf})"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 210, "the reference holds 7 tables × 30 queries");
}
