//! Point fields as the `DataArray_t` nodes of a `FlowSolution_t`, and back: a scalar
//! is one array named as the field; 2 or 3 components are `<name>X`, `<name>Y`
//! (`<name>Z`); 9 (a row-major 3x3 tensor, the metric) are `<name>XX`, `XY`, `XZ`,
//! `YX`, … `ZZ`, the suffixes ParaView's CGNS reader assembles into vectors and
//! tensors; other counts `<name>_0`, `<name>_1`, …. Names are CGNS names (at most 32
//! characters, no `/`).

use std::collections::{BTreeMap, BTreeSet};

use crate::DataArray;

const XYZ: [&str; 3] = ["X", "Y", "Z"];
const TENSOR: [&str; 9] = ["XX", "XY", "XZ", "YX", "YY", "YZ", "ZX", "ZY", "ZZ"];

/// The component suffixes of a field of `components` components.
pub(super) fn suffixes(components: usize) -> Vec<String> {
    match components {
        1 => vec![String::new()],
        2 | 3 => XYZ[..components].iter().map(|s| s.to_string()).collect(),
        9 => TENSOR.iter().map(|s| s.to_string()).collect(),
        n => (0..n).map(|i| format!("_{i}")).collect(),
    }
}

/// The columns as one item-major array (`columns[c][i]` is component `c` of item `i`).
fn interleave(columns: &[&Vec<f64>]) -> DataArray {
    let len = columns.first().map_or(0, |c| c.len());
    let values = (0..len).flat_map(|i| columns.iter().map(move |c| c[i])).collect();
    DataArray::new(columns.len(), values)
}

/// Splits the arrays of one `FlowSolution_t` (name → values, file order) into fields:
/// a base name whose every suffix of a known pattern is present (arrays of one length)
/// is one field of that many components; every other array is a scalar. Longest
/// patterns first, so that `metricXX` is never read as a vector `metricX…`.
/// Deterministic: fields by name.
pub(super) fn assemble(arrays: Vec<(String, Vec<f64>)>) -> BTreeMap<String, DataArray> {
    let by_name: BTreeMap<String, Vec<f64>> = arrays.into_iter().collect();
    let mut used: BTreeSet<String> = BTreeSet::new();
    let mut out = BTreeMap::new();
    let complete = |names: &[String], used: &BTreeSet<String>| {
        let len = by_name.get(&names[0]).map(|v| v.len());
        names.len() > 1
            && names.iter().all(|n| by_name.get(n).map(|v| v.len()) == len && !used.contains(n))
    };
    for name in by_name.keys() {
        for pattern in [9usize, 3, 2] {
            let suf = suffixes(pattern);
            let Some(base) = name.strip_suffix(suf[0].as_str()).filter(|b| !b.is_empty()) else {
                continue;
            };
            let names: Vec<String> = suf.iter().map(|s| format!("{base}{s}")).collect();
            // A 2-vector only when no Z completes it (that is a 3-vector).
            if !complete(&names, &used)
                || (pattern == 2 && by_name.contains_key(&format!("{base}Z")))
            {
                continue;
            }
            let columns: Vec<&Vec<f64>> = names.iter().map(|n| &by_name[n]).collect();
            out.insert(base.to_string(), interleave(&columns));
            used.extend(names);
            break;
        }
    }
    // `<name>_0`, `_1`, …: consecutive from 0.
    for name in by_name.keys() {
        let Some(base) = name.strip_suffix("_0").filter(|b| !b.is_empty()) else { continue };
        let names: Vec<String> =
            (0..).map(|i| format!("{base}_{i}")).take_while(|n| by_name.contains_key(n)).collect();
        if complete(&names, &used) {
            let columns: Vec<&Vec<f64>> = names.iter().map(|n| &by_name[n]).collect();
            out.insert(base.to_string(), interleave(&columns));
            used.extend(names);
        }
    }
    for (name, values) in &by_name {
        if !used.contains(name) && !out.contains_key(name) {
            out.insert(name.clone(), DataArray::new(1, values.clone()));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(name: &str, a: &DataArray) -> Vec<(String, Vec<f64>)> {
        suffixes(a.components)
            .iter()
            .enumerate()
            .map(|(c, s)| (format!("{name}{s}"), (0..a.len()).map(|i| a.item(i)[c]).collect()))
            .collect()
    }

    #[test]
    fn fields_split_and_assemble_back() {
        let mut fields = BTreeMap::new();
        fields.insert("metric".to_string(), DataArray::new(9, (0..18).map(f64::from).collect()));
        fields.insert("u".to_string(), DataArray::new(3, (0..6).map(f64::from).collect()));
        fields.insert("p".to_string(), DataArray::new(1, vec![1.0, 2.0]));
        fields.insert("w".to_string(), DataArray::new(2, vec![1.0, 2.0, 3.0, 4.0]));
        fields.insert("q".to_string(), DataArray::new(4, (0..8).map(f64::from).collect()));
        let arrays: Vec<_> = fields.iter().flat_map(|(n, a)| split(n, a)).collect();
        assert_eq!(assemble(arrays), fields);
    }
}
