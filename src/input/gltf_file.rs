//! A glTF or GLB file as every reader of the tool opens it: through the bounded reader, parsed
//! from memory, and its node hierarchy walked as the forest glTF requires it to be.

use std::path::Path;

use glam::DMat4;

/// The glTF or GLB file at `path`, read through the bounded reader (`input::read`) and parsed
/// from memory: the `gltf` crate's own `open` reads a FIFO forever and allocates a GLB header's
/// declared length before reading it (a header claiming 3.9 GB took 7.6 GB).
pub fn open(path: &Path) -> Result<gltf::Gltf, String> {
    let bytes = super::read::read(path, super::read::MESH).map_err(|e| e.to_string())?;
    // The GLB reader subtracts its header's length from a declared one and underflows on a short
    // one: a panic, which becomes the file's error.
    super::guard::without_panics(|| gltf::Gltf::from_slice(&bytes))
        .map_err(|panic| format!("malformed glTF: the glTF reader failed on it ({panic})"))?
        .map_err(|e| format!("cannot read glTF: {e}"))
}

/// A node reached from the scene's roots, with its world transform and the position in the walk
/// of its parent (None for a root).
#[derive(Debug)]
pub struct Placed<'a> {
    pub node: gltf::Node<'a>,
    pub world: DMat4,
    pub parent: Option<usize>,
}

/// The nodes of the document's scene (the default one, else the first; without a scene every
/// node that is no node's child) in depth-first order, each before its children, walked without
/// recursion. glTF requires the hierarchy to be a forest (glTF 2.0 §3.5.3: "node hierarchy MUST
/// be a set of disjoint strict trees"): a node that is its own child, a cycle, or a node with two
/// parents is refused, naming the nodes, before anything is walked — a cycle overflowed the stack
/// and a small DAG of shared children expanded to gigabytes.
pub fn walk(doc: &gltf::Document) -> Result<Vec<Placed<'_>>, String> {
    let count = doc.nodes().count();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in doc.nodes() {
        for child in node.children() {
            let (c, p) = (child.index(), node.index());
            if c == p {
                return Err(format!("node {p} is its own child: glTF's nodes form trees"));
            }
            if let Some(first) = parent[c] {
                return Err(format!(
                    "node {c} is a child of nodes {first} and {p}: a glTF node has at most one parent"
                ));
            }
            parent[c] = Some(p);
        }
    }
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => doc.nodes().filter(|n| parent[n.index()].is_none()).collect(),
    };
    let mut seen = vec![false; count];
    let mut out: Vec<Placed> = Vec::new();
    let mut stack: Vec<(gltf::Node, Option<usize>)> = roots.into_iter().rev().map(|n| (n, None)).collect();
    while let Some((node, up)) = stack.pop() {
        let i = node.index();
        if std::mem::replace(&mut seen[i], true) {
            return Err(match parent[i] {
                Some(p) => format!("node {i} is reached again through node {p}: its nodes form a cycle"),
                None => format!("node {i} is listed twice among the scene's nodes"),
            });
        }
        if up.is_none() && parent[i].is_some() {
            return Err(format!("node {i} is a root of the scene and a child of node {}", parent[i].unwrap_or(0)));
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = up.map_or(DMat4::IDENTITY, |u| out[u].world) * local;
        let at = out.len();
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, Some(at)));
        }
        out.push(Placed { node, world, parent: up });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(nodes: &str, scene_nodes: &str) -> gltf::Gltf {
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":{scene_nodes}}}],"nodes":{nodes}}}"#
        );
        gltf::Gltf::from_slice_without_validation(json.as_bytes()).unwrap()
    }

    #[test]
    fn cycles_shared_children_and_self_children_are_refused() {
        let own = doc(r#"[{"children":[0]}]"#, "[0]");
        assert!(walk(&own).unwrap_err().contains("its own child"));
        let two = doc(r#"[{"children":[1]},{"children":[0]}]"#, "[0]");
        assert!(walk(&two).is_err());
        let shared = doc(r#"[{"children":[2]},{"children":[2]},{}]"#, "[0, 1]");
        assert!(walk(&shared).unwrap_err().contains("at most one parent"));
    }

    #[test]
    fn a_deep_chain_is_walked_without_recursion_in_order() {
        let n = 50_000;
        let nodes: Vec<String> =
            (0..n)
                .map(|i| {
                    if i + 1 < n {
                        format!(r#"{{"children":[{}],"translation":[1,0,0]}}"#, i + 1)
                    } else {
                        "{}".into()
                    }
                })
                .collect();
        let g = doc(&format!("[{}]", nodes.join(",")), "[0]");
        let placed = walk(&g).unwrap();
        assert_eq!(placed.len(), n);
        assert_eq!(placed[n - 1].world.w_axis.x, (n - 1) as f64);
        assert_eq!(placed[1].parent, Some(0));
    }
}
