//! `<bsdf type="tabulated">` (ours): loading a measured table, and its errors.

use gonio_render::xml::load_bsdf_str;

#[test]
fn tabulated_needs_a_readable_table_and_says_where() {
    let e = load_bsdf_str(r#"<bsdf type="tabulated"/>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("needs a filename") && e.contains(":1:"), "{e}");
    let e = load_bsdf_str(r#"<bsdf type="tabulated"><string name="filename" value="no-such.table"/></bsdf>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no-such.table"), "{e}");
}
