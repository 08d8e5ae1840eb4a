//! Shards: `--shard K/N` renders the K-th of N disjoint shares of a matrix's cells, and
//! `--shard auto` reads K and N from the batch scheduler that started the process (a Kubernetes
//! Indexed Job or a Slurm job array). `shadematrix merge` joins the shards' folders into one run.
//!
//! A cell is compared with its reference cell and a twin copies its original, so a share must
//! hold them too. The cells that need each other that way form connected sets; each set goes to
//! one shard whole, so N shards render every original once between them. The sets are dealt out
//! by estimated cost, the largest first, each to the shard with the least so far (Graham's LPT
//! rule), so each shard gets about 1/N of the work; every shard computes the same deal. A set
//! costlier than a shard's share is split into its groups (the cells compared with one reference
//! cell, a twin with its original's), and what a shard then lacks (the original of a twin in
//! another group, or a reference cell) it renders as *support*: full cells, the same bytes the
//! owning shard writes, recorded in `run.json` so `merge` keeps the owner's copy.

use std::collections::{HashMap, HashSet};

use crate::cells::{reference_cell_id, Cell, CellId, Expansion};
use crate::declarations::matrix::{Matrix, ReferenceSpec};
use crate::error::{Error, InputError};

/// A cell's estimated cost: its pixels where it is rendered, a 64th of that where it is a twin
/// (a copy of its original's files and its own metrics).
fn cost(cell: &Cell) -> f64 {
    let pixels = cell.width as f64 * cell.height as f64;
    if cell.twin_of.is_some() {
        pixels / 64.0
    } else {
        pixels
    }
}

/// The cells a cell cannot be rendered without: its original (a twin) and its reference cell.
fn needs(matrix: &Matrix, cell: &Cell) -> impl Iterator<Item = CellId> {
    let reference = match &matrix.reference {
        Some(ReferenceSpec::Cell(terms)) => reference_cell_id(cell, matrix, terms),
        _ => None,
    };
    cell.twin_of.clone().into_iter().chain(reference)
}

/// The root of i's set, halving the path on the way.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Which shard of `n` (1-based) owns each cell, by index in `cells`.
pub fn owners(matrix: &Matrix, cells: &[Cell], n: u32) -> Vec<u32> {
    let index: HashMap<&CellId, usize> = cells.iter().enumerate().map(|(i, c)| (&c.id, i)).collect();
    let needed =
        |i: usize| -> Vec<usize> { needs(matrix, &cells[i]).filter_map(|id| index.get(&id).copied()).collect() };
    // A cell's group: its original's reference cell where the matrix has it, else its original.
    let group: Vec<usize> = (0..cells.len())
        .map(|i| {
            let original = cells[i].twin_of.as_ref().and_then(|o| index.get(o).copied()).unwrap_or(i);
            match &matrix.reference {
                Some(ReferenceSpec::Cell(terms)) => reference_cell_id(&cells[original], matrix, terms)
                    .and_then(|r| index.get(&r).copied())
                    .unwrap_or(original),
                _ => original,
            }
        })
        .collect();
    // The connected sets of "needs" and of groups.
    let mut parent: Vec<usize> = (0..cells.len()).collect();
    for (i, &g) in group.iter().enumerate() {
        for j in needed(i).into_iter().chain([g]) {
            let (a, b) = (root(&mut parent, i), root(&mut parent, j));
            parent[a.max(b)] = a.min(b);
        }
    }
    let total: f64 = cells.iter().map(cost).sum();
    let share = total / n as f64;
    // Units of the deal: a set whole, or its groups where it outweighs a share.
    let mut sets: HashMap<usize, Vec<usize>> = HashMap::new();
    for i in 0..cells.len() {
        let r = root(&mut parent, i);
        sets.entry(r).or_default().push(i);
    }
    let mut units: Vec<(f64, Vec<usize>)> = Vec::new();
    for (_, members) in sets {
        let weight: f64 = members.iter().map(|&i| cost(&cells[i])).sum();
        if weight > share && n > 1 {
            let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
            for i in members {
                groups.entry(group[i]).or_default().push(i);
            }
            units.extend(groups.into_values().map(|g| (g.iter().map(|&i| cost(&cells[i])).sum(), g)));
        } else {
            units.push((weight, members));
        }
    }
    // Largest first; ties by the first cell's id, so every shard deals the same.
    for (_, members) in &mut units {
        members.sort_unstable();
    }
    units.sort_by(|(wa, a), (wb, b)| wb.total_cmp(wa).then_with(|| cells[a[0]].id.0.cmp(&cells[b[0]].id.0)));
    let mut load = vec![0.0f64; n as usize];
    let mut owner = vec![0u32; cells.len()];
    for (weight, members) in units {
        let k = (0..n as usize).min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b))).unwrap_or(0);
        load[k] += weight;
        for i in members {
            owner[i] = k as u32 + 1;
        }
    }
    owner
}

/// Keep shard `k` of `n` of `exp`, with the support cells it needs.
pub fn select(matrix: &Matrix, exp: &mut Expansion, (k, n): (u32, u32)) {
    let by_id: HashMap<&CellId, &Cell> = exp.cells.iter().map(|c| (&c.id, c)).collect();
    let owner = owners(matrix, &exp.cells, n);
    let own: HashSet<CellId> =
        exp.cells.iter().zip(&owner).filter(|(_, &o)| o == k).map(|(c, _)| c.id.clone()).collect();
    let mut needed: HashSet<CellId> = own.clone();
    let mut queue: Vec<&Cell> = exp.cells.iter().filter(|c| own.contains(&c.id)).collect();
    while let Some(c) = queue.pop() {
        for id in needs(matrix, c) {
            if let Some(d) = by_id.get(&id) {
                if needed.insert(id) {
                    queue.push(d);
                }
            }
        }
    }
    exp.support =
        exp.cells.iter().filter(|c| needed.contains(&c.id) && !own.contains(&c.id)).map(|c| c.id.clone()).collect();
    exp.cells.retain(|c| needed.contains(&c.id));
}

/// Where `--shard auto` finds its index, in the order looked for.
pub const AUTO_SOURCES: &str = "JOB_COMPLETION_INDEX (Kubernetes Indexed Job; give N as --shard auto/N or \
     SHADEMATRIX_SHARDS), or SLURM_ARRAY_TASK_ID with SLURM_ARRAY_TASK_COUNT and SLURM_ARRAY_TASK_MIN (Slurm job array)";

/// `--shard` as (k, n): `K/N`, `auto` or `auto/N`, reading the scheduler's variables from `env`.
pub fn parse(value: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<(u32, u32), Error> {
    let key = |why: String| -> Error { InputError::at_key("command line", "--shard", why).into() };
    let number = |name: &str, v: &str| -> Result<u32, Error> {
        v.trim().parse::<u32>().map_err(|_| key(format!("{name}=`{v}` is not a whole number")))
    };
    let (head, given_n) = match value.split_once('/') {
        Some((h, n)) => (h.trim(), Some(n)),
        None => (value.trim(), None),
    };
    let (k, n) = if head == "auto" {
        let n_given = match given_n {
            Some(n) => Some(number("N", n)?),
            None => env("SHADEMATRIX_SHARDS").map(|v| number("SHADEMATRIX_SHARDS", &v)).transpose()?,
        };
        if let Some(index) = env("JOB_COMPLETION_INDEX") {
            let n = n_given.ok_or_else(|| {
                key("JOB_COMPLETION_INDEX is set, but not the completions count: pass --shard auto/N (N = the Job's completions) or set SHADEMATRIX_SHARDS".into())
            })?;
            // The index is 0-based; its largest value would wrap to shard 0 (u32::MAX + 1).
            let i = number("JOB_COMPLETION_INDEX", &index)?;
            let k = i.checked_add(1).ok_or_else(|| {
                key(format!("JOB_COMPLETION_INDEX={i} is past any Job's completions (at most {})", u32::MAX - 1))
            })?;
            (k, n)
        } else if let Some(task) = env("SLURM_ARRAY_TASK_ID") {
            let task = number("SLURM_ARRAY_TASK_ID", &task)?;
            let min = env("SLURM_ARRAY_TASK_MIN").map(|v| number("SLURM_ARRAY_TASK_MIN", &v)).transpose()?.unwrap_or(0);
            let count = env("SLURM_ARRAY_TASK_COUNT").map(|v| number("SLURM_ARRAY_TASK_COUNT", &v)).transpose()?;
            let n = n_given.or(count).ok_or_else(|| {
                key("SLURM_ARRAY_TASK_ID is set, but not SLURM_ARRAY_TASK_COUNT: pass --shard auto/N".into())
            })?;
            if task < min {
                return Err(key(format!("SLURM_ARRAY_TASK_ID={task} is below SLURM_ARRAY_TASK_MIN={min}")));
            }
            let k = (task - min).checked_add(1).ok_or_else(|| {
                key(format!("SLURM_ARRAY_TASK_ID={task} is past any array's tasks (at most {})", u32::MAX - 1))
            })?;
            (k, n)
        } else {
            return Err(key(format!("`auto` found no scheduler index; it reads {AUTO_SOURCES}")));
        }
    } else {
        let n = given_n.ok_or_else(|| key(format!("`{value}` is not K/N, auto or auto/N")))?;
        (number("K", head)?, number("N", n)?)
    };
    if k == 0 || n == 0 || k > n {
        return Err(key(format!("`{value}` gives shard {k} of {n}; it needs 1 <= K <= N")));
    }
    Ok((k, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| vars.iter().find(|(n, _)| *n == k).map(|(_, v)| v.to_string())
    }

    fn shipped(name: &str) -> Matrix {
        let path = format!("{}/matrices/{name}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        Matrix::from_text(&path, &text, None, std::sync::Arc::new(crate::shading::Registry::builtin())).unwrap()
    }

    /// Per shard of n: (cells it owns, originals it renders, support cells), and the sum of
    /// owned cells' costs.
    fn deal(m: &Matrix, n: u32) -> Vec<(usize, usize, usize, f64)> {
        (1..=n)
            .map(|k| {
                let mut e = crate::cells::expand(m);
                let costs: HashMap<CellId, f64> = e.cells.iter().map(|c| (c.id.clone(), cost(c))).collect();
                select(m, &mut e, (k, n));
                let support: HashSet<&CellId> = e.support.iter().collect();
                let owned: Vec<&Cell> = e.cells.iter().filter(|c| !support.contains(&c.id)).collect();
                let weight = owned.iter().map(|c| costs[&c.id]).sum();
                (owned.len(), e.rendered().count(), e.support.len(), weight)
            })
            .collect()
    }

    #[test]
    fn shards_render_each_original_once_and_share_the_work() {
        // bench.toml: 432 cells in sets of one composition and preset (Lambert's smoothness twins
        // join the three reference groups of their original). Four shards deal them whole.
        let m = shipped("bench.toml");
        let all = crate::cells::expand(&m);
        let total: f64 = all.cells.iter().map(cost).sum();
        for n in [2, 3, 4] {
            let shards = deal(&m, n);
            assert_eq!(shards.iter().map(|s| s.0).sum::<usize>(), all.cells.len(), "every cell owned once, n = {n}");
            assert_eq!(shards.iter().map(|s| s.2).sum::<usize>(), 0, "no support cell, n = {n}: {shards:?}");
            assert_eq!(
                shards.iter().map(|s| s.1).sum::<usize>(),
                all.rendered().count(),
                "each original rendered once, n = {n}"
            );
            // 16 equal sets: an even deal for 2 and 4, at most one set over the share for 3.
            let worst = shards.iter().map(|s| s.3).fold(0.0, f64::max);
            assert!(worst <= total / n as f64 + total / 16.0 + 1e-6, "n = {n}: {shards:?}");
        }
    }

    #[test]
    fn a_set_larger_than_a_share_is_split_into_groups_with_support() {
        // Everything compared with one reference cell would be one set: split by reference group
        // it still gives every shard a share, the cells it needs rendered as support.
        let text = "name = \"one\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"gold\", \"plastic\"]\nreference = { pipeline = \"hdrp\", shader = \"lit\" }\n[sweep]\nsmoothness = [0.3, 0.8]\n[image]\nwidth = 32\nheight = 32\n";
        let m = Matrix::from_text("one.toml", text, None, std::sync::Arc::new(crate::shading::Registry::builtin()))
            .unwrap();
        // Two sets (one a preset) of 8 cells: two shards take one each, whole.
        let two = deal(&m, 2);
        assert!(two.iter().all(|s| s.0 == 8 && s.2 == 0), "{two:?}");
        // Three shards: the sets outweigh a third, so their groups are dealt; none is left empty.
        let three = deal(&m, 3);
        assert!(three.iter().all(|s| s.0 > 0), "{three:?}");
        assert!(three.iter().map(|s| s.2).sum::<usize>() > 0, "{three:?}");
        assert_eq!(three.iter().map(|s| s.0).sum::<usize>(), 16);
    }

    #[test]
    fn reads_each_scheduler_and_refuses_what_it_cannot_place() {
        assert_eq!(parse("2/5", &env(&[])).unwrap(), (2, 5));
        // Kubernetes: a 0-based index; the count is not in the environment.
        assert_eq!(parse("auto/4", &env(&[("JOB_COMPLETION_INDEX", "0")])).unwrap(), (1, 4));
        assert_eq!(parse("auto", &env(&[("JOB_COMPLETION_INDEX", "3"), ("SHADEMATRIX_SHARDS", "4")])).unwrap(), (4, 4));
        assert!(parse("auto", &env(&[("JOB_COMPLETION_INDEX", "3")])).is_err());
        // The largest index does not wrap to shard 0 (it was taken as shard 1 of N, silently).
        let err = parse("auto/4", &env(&[("JOB_COMPLETION_INDEX", "4294967295")])).unwrap_err();
        assert!(err.to_string().contains("4294967295"), "{err}");
        assert!(parse("auto/3", &env(&[("JOB_COMPLETION_INDEX", "3")])).is_err());
        // Slurm: --array=1-8 numbers tasks from SLURM_ARRAY_TASK_MIN.
        let slurm = [("SLURM_ARRAY_TASK_ID", "8"), ("SLURM_ARRAY_TASK_COUNT", "8"), ("SLURM_ARRAY_TASK_MIN", "1")];
        assert_eq!(parse("auto", &env(&slurm)).unwrap(), (8, 8));
        assert_eq!(
            parse("auto", &env(&[("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_COUNT", "3")])).unwrap(),
            (1, 3)
        );
        let e = parse("auto", &env(&[])).unwrap_err().to_string();
        assert!(e.contains("JOB_COMPLETION_INDEX") && e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
        assert!(
            parse("0/3", &env(&[])).is_err() && parse("4/3", &env(&[])).is_err() && parse("x/3", &env(&[])).is_err()
        );
    }
}
