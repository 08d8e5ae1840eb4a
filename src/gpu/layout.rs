//! CPU mirrors of WGSL structs (`#[repr(C)]` + bytemuck) checked against the WGSL itself: naga
//! lays out each struct as the shader compiler will (size and member offsets), and a mirror must
//! match it member for member. A size test alone passes two swapped `vec4`s.

/// A WGSL struct's size and its members' names and byte offsets, as naga lays them out.
pub fn wgsl_struct(source: &str, name: &str) -> Result<(u32, Vec<(String, u32)>), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| format!("WGSL does not parse: {}", e.message()))?;
    let found = module
        .types
        .iter()
        .find_map(|(_, ty)| match (&ty.name, &ty.inner) {
            (Some(n), naga::TypeInner::Struct { members, span }) if n == name => {
                Some((*span, members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect()))
            }
            _ => None,
        })
        .ok_or_else(|| format!("no struct `{name}` in the WGSL"));
    found
}

/// Whether the CPU mirror (its size and each field's name and offset, in declaration order)
/// matches the WGSL struct `name`; the error lists every difference.
pub fn check_mirror(source: &str, name: &str, size: usize, fields: &[(&str, usize)]) -> Result<(), String> {
    let (span, members) = wgsl_struct(source, name)?;
    let mut bad = Vec::new();
    if span as usize != size {
        bad.push(format!("size: WGSL {span}, Rust {size}"));
    }
    if members.len() != fields.len() {
        bad.push(format!("members: WGSL {}, Rust {}", members.len(), fields.len()));
    }
    for ((wname, woffset), (rname, roffset)) in members.iter().zip(fields) {
        if wname != rname || *woffset as usize != *roffset {
            bad.push(format!("WGSL `{wname}` at {woffset}, Rust `{rname}` at {roffset}"));
        }
    }
    match bad.is_empty() {
        true => Ok(()),
        false => Err(format!("`{name}`: {}", bad.join("; "))),
    }
}

/// `(size, [(field, offset)…])` of a `#[repr(C)]` type, for `check_mirror`.
#[macro_export]
macro_rules! mirror_layout {
    ($ty:ty, [$($field:ident),* $(,)?]) => {
        (std::mem::size_of::<$ty>(), vec![$((stringify!($field), std::mem::offset_of!($ty, $field))),*])
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[repr(C)]
    struct Pair {
        a: [f32; 4],
        b: [f32; 2],
    }

    #[test]
    fn a_swapped_or_misplaced_member_is_found() {
        let wgsl = "struct Pair { a: vec4<f32>, b: vec2<f32> };\n";
        let (size, fields) = crate::mirror_layout!(Pair, [a, b]);
        let _ = Pair { a: [0.0; 4], b: [0.0; 2] }.a;
        // WGSL rounds the struct up to its 16-byte alignment; the Rust mirror here does not.
        let err = check_mirror(wgsl, "Pair", size, &fields).unwrap_err();
        assert!(err.contains("size: WGSL 32, Rust 24"), "{err}");
        let swapped = "struct Pair { b: vec2<f32>, a: vec4<f32> };\n";
        assert!(check_mirror(swapped, "Pair", 32, &fields).unwrap_err().contains("WGSL `b` at 0"));
    }
}
