//! Property elements (`<float>`, `<rgb>`, `<spectrum>`, `<point>`, ...) and `<transform>`
//! blocks: their values, parsed and checked, for the parser ([`super::parse`]).

use super::doc::resolve_path;
use super::doc::{Prop, Value};
use super::error::{ErrorKind, Location, SceneError};
use super::parse::{Attrs, FileCtx, Parser};
use super::values;
use glam::{DMat4, DVec3};

impl Parser {
    pub(super) fn property(
        &mut self,
        ctx: &FileCtx,
        node: roxmltree::Node,
        tag: &str,
    ) -> Result<Prop, SceneError> {
        let loc = ctx.loc(node);
        let allowed: &[&str] = match tag {
            "point" | "vector" => &["name", "value", "x", "y", "z"],
            "spectrum" => &["name", "value", "filename"],
            "transform" => &["name"],
            _ => &["name", "value"],
        };
        let attrs = self.attrs(ctx, node, allowed)?;
        let (raw_name, _) = attrs.required("name", tag)?;
        let name = self.prop_name(ctx, raw_name);
        if tag != "transform"
            && let Some(c) = node.children().find(|c| c.is_element())
        {
            return Err(SceneError::new(
                ctx.loc(c),
                ErrorKind::Grammar,
                format!("<{tag}> cannot contain <{}>", c.tag_name().name()),
            ));
        }
        let (value, value_loc) = match tag {
            "integer" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Int(values::parse_int(v, l)?), l.clone())
            }
            "float" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Float(values::parse_float(v, l)?), l.clone())
            }
            "boolean" => {
                let (v, l) = attrs.required("value", tag)?;
                let b = match v.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => {
                        return Err(SceneError::new(
                            l.clone(),
                            ErrorKind::BadValue,
                            format!("invalid boolean \"{v}\" (expected true or false)"),
                        ));
                    }
                };
                (Value::Bool(b), l.clone())
            }
            "string" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Str(v.to_owned()), l.clone())
            }
            "point" | "vector" => {
                let (p, l) = xyz_or_value(&attrs, tag, 0.0)?;
                (
                    if tag == "point" {
                        Value::Point(p)
                    } else {
                        Value::Vector(p)
                    },
                    l,
                )
            }
            "rgb" => {
                let (v, l) = attrs.required("value", tag)?;
                let n = values::parse_list(v, l)?;
                let c = match n.as_slice() {
                    [x] => [*x; 3],
                    [r, g, b] => [*r, *g, *b],
                    _ => {
                        return Err(SceneError::new(
                            l.clone(),
                            ErrorKind::BadValue,
                            format!("<rgb> needs 1 or 3 numbers, found \"{v}\""),
                        ));
                    }
                };
                (Value::Rgb(c), l.clone())
            }
            "spectrum" => match (attrs.get("value"), attrs.get("filename")) {
                (Some((v, l)), None) => (Value::Spectrum(values::parse_spectrum_value(v, l)?), l.clone()),
                (None, Some((f, l))) => {
                    let path = resolve_path(&ctx.dir, &self.doc.search_paths, f);
                    (Value::Spectrum(values::read_spd(&path, f, l)?), l.clone())
                }
                _ => {
                    return Err(SceneError::new(
                        loc,
                        ErrorKind::Grammar,
                        "<spectrum> needs exactly one of \"value\" and \"filename\"",
                    ));
                }
            },
            "transform" => (Value::Transform(self.transform(ctx, node)?), loc.clone()),
            _ => unreachable!("property tags are matched by the caller"),
        };
        Ok(Prop {
            name,
            value,
            loc,
            value_loc,
        })
    }

    /// `<transform>`: each operation left-multiplies, so operations apply in document order.
    pub(super) fn transform(&mut self, ctx: &FileCtx, node: roxmltree::Node) -> Result<DMat4, SceneError> {
        let mut m = DMat4::IDENTITY;
        for c in node.children() {
            if c.is_text() {
                if c.text().is_some_and(|t| !t.trim().is_empty()) {
                    return Err(SceneError::new(
                        ctx.loc(c),
                        ErrorKind::Grammar,
                        "unexpected text in <transform>",
                    ));
                }
                continue;
            }
            if !c.is_element() {
                continue;
            }
            let tag = c.tag_name().name();
            let op = match tag {
                "translate" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z"])?;
                    let (t, _) = xyz_or_value(&attrs, tag, 0.0)?;
                    DMat4::from_translation(t)
                }
                "scale" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z"])?;
                    let (s, _) = xyz_or_value(&attrs, tag, 1.0)?;
                    DMat4::from_scale(s)
                }
                "rotate" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z", "angle"])?;
                    let (axis, aloc) = xyz_or_value(&attrs, tag, 0.0)?;
                    let (a, l) = attrs.required("angle", tag)?;
                    let angle = values::parse_float(a, l)?;
                    if axis.length_squared() == 0.0 {
                        return Err(SceneError::new(
                            aloc,
                            ErrorKind::BadValue,
                            "<rotate> axis is zero (give value=\"x, y, z\" or x/y/z attributes)",
                        ));
                    }
                    DMat4::from_axis_angle(axis.normalize(), angle.to_radians())
                }
                "matrix" => {
                    let attrs = self.attrs(ctx, c, &["value"])?;
                    let (v, l) = attrs.required("value", tag)?;
                    let n = values::parse_list(v, l)?;
                    match n.len() {
                        16 => DMat4::from_cols_array(&[
                            n[0], n[4], n[8], n[12], n[1], n[5], n[9], n[13], n[2], n[6], n[10], n[14], n[3],
                            n[7], n[11], n[15],
                        ]),
                        9 => DMat4::from_cols_array(&[
                            n[0], n[3], n[6], 0.0, n[1], n[4], n[7], 0.0, n[2], n[5], n[8], 0.0, 0.0, 0.0,
                            0.0, 1.0,
                        ]),
                        k => {
                            return Err(SceneError::new(
                                l.clone(),
                                ErrorKind::BadValue,
                                format!("<matrix> needs 16 (or 9) numbers, found {k} in \"{v}\""),
                            ));
                        }
                    }
                }
                "lookat" => {
                    let attrs = self.attrs(ctx, c, &["origin", "target", "up"])?;
                    let (o, ol) = attrs.required("origin", tag)?;
                    let origin = values::parse_vec3(o, ol)?;
                    let (t, tl) = attrs.required("target", tag)?;
                    let target = values::parse_vec3(t, tl)?;
                    let up = match attrs.get("up") {
                        Some((u, ul)) => Some((values::parse_vec3(u, ul)?, ul.clone())),
                        None => None,
                    };
                    values::look_at(origin, target, up.as_ref().map(|(u, _)| *u)).map_err(|msg| {
                        let l = match &up {
                            Some((_, ul)) if msg.contains("up") => ul.clone(),
                            _ => tl.clone(),
                        };
                        SceneError::new(l, ErrorKind::BadValue, msg)
                    })?
                }
                _ => {
                    return Err(SceneError::new(
                        ctx.loc(c),
                        ErrorKind::Grammar,
                        format!(
                            "unknown transform operation <{tag}> (expected translate, rotate, scale, matrix, lookat)"
                        ),
                    ));
                }
            };
            if let Some(x) = c.children().find(|x| x.is_element()) {
                return Err(SceneError::new(
                    ctx.loc(x),
                    ErrorKind::Grammar,
                    format!("<{tag}> cannot contain <{}>", x.tag_name().name()),
                ));
            }
            m = op * m;
        }
        Ok(m)
    }
}

/// `value="x, y, z"` (1 number is replicated) or x/y/z attributes (missing ones = `missing`).
fn xyz_or_value(attrs: &Attrs, tag: &str, missing: f64) -> Result<(DVec3, Location), SceneError> {
    let has_xyz = attrs.has("x") || attrs.has("y") || attrs.has("z");
    match attrs.get("value") {
        Some((v, l)) => {
            if has_xyz {
                return Err(SceneError::new(
                    l.clone(),
                    ErrorKind::Grammar,
                    format!("<{tag}> has both \"value\" and x/y/z attributes"),
                ));
            }
            Ok((values::parse_vec3(v, l)?, l.clone()))
        }
        None => {
            if !has_xyz && tag != "translate" && tag != "scale" && tag != "rotate" {
                return Err(SceneError::new(
                    attrs.elem.clone(),
                    ErrorKind::Grammar,
                    format!("<{tag}> needs \"value\" or x/y/z attributes"),
                ));
            }
            let mut p = [missing; 3];
            for (i, k) in ["x", "y", "z"].iter().enumerate() {
                if let Some((v, l)) = attrs.get(k) {
                    p[i] = values::parse_float(v, l)?;
                }
            }
            Ok((DVec3::from_array(p), attrs.elem.clone()))
        }
    }
}
