//! The model written back in the libconfig of appendix A.

use std::fmt::Write as _;

use crate::recipe::model::{EntityRef, FunctionSpec, Recipe, SpecValue};
use crate::recipe::{LayerSpec, PeriodicSpec};
use crate::sizing::algorithms::INFINITE_NORM;

/// A libconfig string literal.
fn quote(s: &str) -> String {
    let mut o = String::with_capacity(s.len() + 2);
    o.push('"');
    for c in s.chars() {
        match c {
            '\\' => o.push_str("\\\\"),
            '"' => o.push_str("\\\""),
            '\n' => o.push_str("\\n"),
            '\r' => o.push_str("\\r"),
            '\t' => o.push_str("\\t"),
            '\u{c}' => o.push_str("\\f"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\x{:02x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

/// A float that libconfig reads back as a float, exactly (shortest round-trip form).
fn float(v: f64) -> String {
    format!("{v:?}")
}

fn name_list(names: &[String]) -> String {
    let v: Vec<String> = names.iter().map(|n| quote(n)).collect();
    format!("( {} )", v.join(", "))
}

/// The model in the libconfig of appendix A.
pub fn write(r: &Recipe) -> String {
    let mut o = String::from("// smartmesh sizing recipe (libconfig, thesis appendix A)\n");
    let g = &r.global;
    for (key, v) in [
        ("HMIN", g.h_min),
        ("HMAX", g.h_max),
        ("MAX_ASPECT_RATIO", g.max_aspect_ratio),
        ("GRADATION", g.gradation),
    ] {
        if let Some(v) = v {
            let _ = writeln!(o, "{key} = {};", float(v));
        }
    }
    let list = |o: &mut String, key: &str, items: Vec<String>| {
        if !items.is_empty() {
            let _ = writeln!(o, "\n{key} =\n(\n{}\n);", items.join(",\n"));
        }
    };
    list(
        &mut o,
        "CREATE_REGIONS",
        r.regions
            .iter()
            .map(|(name, ents)| {
                let all_tags = ents.iter().all(|e| matches!(e, EntityRef::Tag(_)));
                let all_names = ents.iter().all(|e| matches!(e, EntityRef::Name(_)));
                let items: Vec<String> = ents
                    .iter()
                    .map(|e| match e {
                        EntityRef::Tag(t) => t.to_string(),
                        EntityRef::Name(n) => quote(n),
                    })
                    .collect();
                // An array holds one scalar type; a mixed region needs a list.
                let (open, close) = if all_tags || all_names { ("[", "]") } else { ("(", ")") };
                format!(
                    "    {{ NAME = {}; TOPOLOGICAL_ENTITIES = {open} {} {close}; }}",
                    quote(name),
                    items.join(", ")
                )
            })
            .collect(),
    );
    list(
        &mut o,
        "CREATE_POLYLINES",
        r.polylines
            .iter()
            .map(|(name, pts)| {
                let coords = |k: usize| -> String {
                    (0..pts.len()).map(|i| float(pts.point(i)[k])).collect::<Vec<_>>().join(", ")
                };
                let z = match pts.components() {
                    3 => format!(";\n      Z_COORDS = [ {} ]", coords(2)),
                    _ => String::new(),
                };
                format!(
                    "    {{ NAME = {};\n      X_COORDS = [ {} ];\n      Y_COORDS = [ {} ]{z}; }}",
                    quote(name),
                    coords(0),
                    coords(1)
                )
            })
            .collect(),
    );
    let functions = |kind: &str| -> Vec<String> {
        r.functions
            .iter()
            .filter(|(_, f)| f.kind_name() == kind)
            .map(|(name, f)| {
                let body = match *f {
                    FunctionSpec::Distance {
                        size_at_source,
                        size_at_max_distance,
                        max_distance,
                        exponent,
                    } => format!(
                        "MINSIZE = {}; MAXSIZE = {}; MAXDISTANCE = {}; EXPONENT = {};",
                        float(size_at_source),
                        float(size_at_max_distance),
                        float(max_distance),
                        float(exponent)
                    ),
                    FunctionSpec::Projection { size_at_max_distance, max_distance, exponent } => {
                        format!(
                            "MAXSIZE = {}; MAXDISTANCE = {}; EXPONENT = {};",
                            float(size_at_max_distance),
                            float(max_distance),
                            float(exponent)
                        )
                    }
                    FunctionSpec::CurvatureToSize { min_size, max_size, size_of_error } => {
                        format!(
                            "MINSIZE = {}; MAXSIZE = {}; SIZE_OF_ERROR = {};",
                            float(min_size),
                            float(max_size),
                            float(size_of_error)
                        )
                    }
                };
                format!("    {{ NAME = {}; {body} }}", quote(name))
            })
            .collect()
    };
    list(&mut o, "CREATE_DISTANCE_FUNCTIONS", functions("distance"));
    list(&mut o, "CREATE_PROJECTION_FUNCTIONS", functions("projection"));
    list(&mut o, "CREATE_CURVATURE_TO_SIZE_FUNCTIONS", functions("curvature-to-size"));
    list(
        &mut o,
        "CREATE_ALGORITHMS",
        r.algorithms
            .iter()
            .map(|a| {
                let mut body = String::new();
                let mut new_line = true;
                for (p, v) in a.arguments() {
                    let value = match v {
                        SpecValue::Names(n) if n.is_empty() && p.kind.is_optional() => continue,
                        SpecValue::Names(n) => name_list(n),
                        SpecValue::Name(n) => quote(n),
                        SpecValue::Size(x) if x.is_infinite() => quote(INFINITE_NORM),
                        SpecValue::Size(x) => float(*x),
                        SpecValue::Absent => continue,
                    };
                    if !new_line {
                        body.push(' ');
                    }
                    let _ = write!(body, "{} = {value};", p.keys[0]);
                    new_line = p.line_break_after;
                    if new_line {
                        body.push_str("\n      ");
                    }
                }
                let body = body.trim_end();
                format!("    {{ TYPE = \"{}\"; {body} }}", a.keyword())
            })
            .collect(),
    );
    if let Some(l) = &r.layer {
        write_layer(&mut o, l);
    }
    if !r.periodic.is_empty() {
        write_periodic(&mut o, &r.periodic);
    }
    o
}

/// The `LAYER` group of a recipe's boundary-layer skin.
fn write_layer(o: &mut String, l: &LayerSpec) {
    let ent = |e: &EntityRef| match e {
        EntityRef::Tag(t) => t.to_string(),
        EntityRef::Name(n) => quote(n),
    };
    let all_tags = l.curves.iter().all(|e| matches!(e, EntityRef::Tag(_)));
    let all_names = l.curves.iter().all(|e| matches!(e, EntityRef::Name(_)));
    let (open, close) = if all_tags || all_names { ("[", "]") } else { ("(", ")") };
    let items: Vec<String> = l.curves.iter().map(ent).collect();
    let _ = write!(o, "\nLAYER =\n{{\n    CURVES = {open} {} {close};\n", items.join(", "));
    for (key, v) in [
        ("FIRST_HEIGHT", l.first_height),
        ("RATIO", l.ratio),
        ("THICKNESS", l.thickness),
        ("Y_PLUS", l.y_plus),
        ("REYNOLDS", l.reynolds),
        ("REF_LENGTH", l.ref_length),
        ("FAN_ANGLE", l.fan_angle),
        ("GAP_RATIO", l.gap_ratio),
    ] {
        if let Some(v) = v {
            let _ = writeln!(o, "    {key} = {};", float(v));
        }
    }
    if let Some(n) = l.layers {
        let _ = writeln!(o, "    LAYERS = {n};");
    }
    if let Some(t) = l.tag {
        let _ = writeln!(o, "    TAG = {t};");
    }
    if l.split {
        let _ = writeln!(o, "    SPLIT = true;");
    }
    if !l.per_curve.is_empty() {
        let items: Vec<String> = l
            .per_curve
            .iter()
            .map(|p| {
                let mut g = format!("        {{ CURVE = {};", ent(&p.curve));
                if let Some(h) = p.first_height {
                    let _ = write!(g, " FIRST_HEIGHT = {};", float(h));
                }
                if let Some(r) = p.ratio {
                    let _ = write!(g, " RATIO = {};", float(r));
                }
                g.push_str(" }");
                g
            })
            .collect();
        let _ = writeln!(o, "    PER_CURVE =\n    (\n{}\n    );", items.join(",\n"));
    }
    o.push_str("};\n");
}

/// The `PERIODIC` list of a recipe's pairs of periodic sides.
fn write_periodic(o: &mut String, periodic: &[PeriodicSpec]) {
    let curves = |list: &[EntityRef]| {
        let items: Vec<String> = list
            .iter()
            .map(|e| match e {
                EntityRef::Tag(t) => t.to_string(),
                EntityRef::Name(n) => quote(n),
            })
            .collect();
        let same = list.iter().all(|e| matches!(e, EntityRef::Tag(_)))
            || list.iter().all(|e| matches!(e, EntityRef::Name(_)));
        let (open, close) = if same { ("[", "]") } else { ("(", ")") };
        format!("{open} {} {close}", items.join(", "))
    };
    let point = |p: [f64; 2]| format!("[ {}, {} ]", float(p[0]), float(p[1]));
    let items: Vec<String> = periodic
        .iter()
        .map(|p| {
            let mut g =
                format!("    {{ MASTER = {}; SLAVE = {};", curves(&p.master), curves(&p.slave));
            if let Some(t) = p.translation {
                let _ = write!(g, " TRANSLATION = {};", point(t));
            }
            if let Some(c) = p.centre {
                let _ = write!(g, " CENTRE = {};", point(c));
            }
            if let Some(a) = p.angle {
                let _ = write!(g, " ANGLE = {};", float(a));
            }
            g.push_str(" }");
            g
        })
        .collect();
    let _ = write!(o, "\nPERIODIC =\n(\n{}\n);\n", items.join(",\n"));
}
