//! Shards: `--shard K/N` renders the K-th of N disjoint shares of a matrix's cells, and
//! `--shard auto` reads K and N from the batch scheduler that started the process (a Kubernetes
//! Indexed Job or a Slurm job array). `shadematrix merge` joins the shards' folders into one run.
//!
//! A cell is compared with its reference cell and a twin copies its original, so a share must
//! hold them too. Cells are dealt out by group — the reference cell of the cell's original (a
//! twin's original, else the cell itself), or that original when there is no reference cell — so
//! a reference lands in the shard of the cells compared with it. What a share still lacks (the
//! original of a twin of another group, and what that one needs) it renders as *support*: full
//! cells, the same bytes the owning shard writes, recorded in `run.json` so `merge` keeps the
//! owner's copy.

use std::collections::{HashMap, HashSet};

use sha2::{Digest, Sha256};

use crate::cells::{reference_cell_id, Cell, CellId, Expansion};
use crate::declarations::matrix::{Matrix, ReferenceSpec};
use crate::error::{Error, InputError};

/// Which shard of `n` (1-based) owns `cell`.
pub fn owner(matrix: &Matrix, cells: &HashMap<&CellId, &Cell>, cell: &Cell, n: u32) -> u32 {
    let original = cell.twin_of.as_ref().and_then(|o| cells.get(o).copied()).unwrap_or(cell);
    let group = match &matrix.reference {
        Some(ReferenceSpec::Cell(terms)) => {
            reference_cell_id(original, matrix, terms).filter(|r| cells.contains_key(r)).unwrap_or(original.id.clone())
        }
        _ => original.id.clone(),
    };
    let h = Sha256::digest(group.0.as_bytes());
    (u32::from_le_bytes([h[0], h[1], h[2], h[3]]) % n) + 1
}

/// Keep shard `k` of `n` of `exp`, with the support cells it needs.
pub fn select(matrix: &Matrix, exp: &mut Expansion, (k, n): (u32, u32)) {
    let by_id: HashMap<&CellId, &Cell> = exp.cells.iter().map(|c| (&c.id, c)).collect();
    let own: HashSet<CellId> =
        exp.cells.iter().filter(|c| owner(matrix, &by_id, c, n) == k).map(|c| c.id.clone()).collect();
    let mut needed: HashSet<CellId> = own.clone();
    let mut queue: Vec<&Cell> = exp.cells.iter().filter(|c| own.contains(&c.id)).collect();
    while let Some(c) = queue.pop() {
        let reference = match &matrix.reference {
            Some(ReferenceSpec::Cell(terms)) => reference_cell_id(c, matrix, terms),
            _ => None,
        };
        for id in c.twin_of.iter().cloned().chain(reference) {
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
