//! `shadematrix merge DIR... --out DIR`: the folders of a sharded run's shards (`run::shard`)
//! joined into one run folder, as if the matrix had run unsharded. Shards must be complete runs of
//! the same matrix (hash) on the same adapter, and together cover every shard of their count;
//! anything else is refused with the folder and the value that differs. Cells are copied (a
//! merged run shares no file with its shards); a support cell comes from the shard that owns it.
//!
//! Nothing a shard's records say is taken on trust: the matrix is loaded again and each shard's
//! expansion and cell keys recomputed (`run::cell_key`). A cell id is a typed single path
//! component (`CellId::parse`) and must be a cell of its shard's recomputed expansion; a cell
//! whose recorded key differs from the recomputed one was rendered from other inputs (another
//! scene file, mesh or tool) and is refused, naming the first input that differs.

use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};

use crate::cells::CellId;
use crate::declarations::matrix::Matrix;
use crate::error::{Error, InputError};
use crate::record::run::{RunStatus, StageTimes};
use crate::record::{CellRecord, Maybe, RunDir, RunRecord, CELL_FILE, RUN_FILE};

pub struct MergeSummary {
    pub dir: PathBuf,
    /// The merged folder's lock, held until its reports are written.
    pub lock: crate::record::RunLock,
    pub cells: usize,
    pub shards: u32,
}

/// Merge the shard folders `inputs` into `out`; `load_matrix` loads the matrix the shards name
/// (their `matrix.origin`), so that their expansion and keys are recomputed from today's files.
pub fn merge(
    inputs: &[PathBuf],
    out: &Path,
    load_matrix: &dyn Fn(&str) -> Result<Matrix, Error>,
) -> Result<MergeSummary, Error> {
    let shown = |p: &Path| p.display().to_string();
    if inputs.is_empty() {
        return Err(InputError::new("command line", "merge needs the shard folders: merge DIR... --out DIR").into());
    }
    let mut shards: BTreeMap<u32, (PathBuf, RunRecord)> = BTreeMap::new();
    let mut count = None;
    for dir in inputs {
        if !dir.join(RUN_FILE).is_file() {
            return Err(InputError::new(shown(dir), "not a run folder (no run.json)").into());
        }
        let r = RunRecord::load(dir)?;
        if r.status != RunStatus::Complete {
            return Err(InputError::at_key(
                shown(&dir.join(RUN_FILE)),
                "status",
                format!(
                    "`{}`: the shard did not finish; continue it with `run --resume --out {}` first",
                    r.status.name(),
                    shown(dir)
                ),
            )
            .into());
        }
        let Some((k, n)) = r.matrix.shard.as_deref().and_then(parse_shard) else {
            return Err(InputError::at_key(
                shown(&dir.join(RUN_FILE)),
                "matrix.shard",
                "absent: not a shard (run with --shard K/N or --shard auto)",
            )
            .into());
        };
        if let Some((_, first)) = shards.values().next() {
            let (a, b) = (&first.matrix.sha256, &r.matrix.sha256);
            if a != b {
                return Err(InputError::at_key(
                    shown(&dir.join(RUN_FILE)),
                    "matrix.sha256",
                    format!("`{b}` differs from the other shards' `{a}`: shards of different matrices do not merge"),
                )
                .into());
            }
            let (a, b) = (adapter_class(first), adapter_class(&r));
            if a != b {
                return Err(InputError::at_key(
                    shown(&dir.join(RUN_FILE)),
                    "adapter",
                    format!("`{b}` differs from the other shards' `{a}`: timings and images compare only within one adapter"),
                )
                .into());
            }
        }
        if *count.get_or_insert(n) != n {
            return Err(InputError::at_key(
                shown(&dir.join(RUN_FILE)),
                "matrix.shard",
                format!("`{k}/{n}`: the other shards are of {}", count.unwrap_or(n)),
            )
            .into());
        }
        if let Some((other, _)) = shards.insert(k, (dir.clone(), r)) {
            return Err(InputError::at_key(
                shown(&dir.join(RUN_FILE)),
                "matrix.shard",
                format!("`{k}/{n}` is also {}", shown(&other)),
            )
            .into());
        }
    }
    let n = count.unwrap_or(1);
    let missing: Vec<String> = (1..=n).filter(|k| !shards.contains_key(k)).map(|k| format!("{k}/{n}")).collect();
    if !missing.is_empty() {
        return Err(InputError::new(
            "command line",
            format!("shard(s) {} missing: give every shard's folder", missing.join(", ")),
        )
        .into());
    }

    let first = shards.values().next().map(|(_, r)| r.clone()).expect("at least one shard");
    let matrix = load_matrix(&first.matrix.origin)?;
    if matrix.hash != first.matrix.sha256 {
        return Err(InputError::at_key(
            first.matrix.origin.clone(),
            "sha256",
            format!(
                "`{}` now; the shards were run from `{}`: the matrix changed since, so their cells are not \
                 its cells (run the shards again)",
                matrix.hash, first.matrix.sha256
            ),
        )
        .into());
    }
    for (k, (src, r)) in &shards {
        check_against_expansion(&matrix, src, r, (*k, n))?;
        check_shard_cells(src, r)?;
    }
    // A merge killed part-way left its own run.json (status `running`, `merged_from` set): merging
    // again into it continues it; any other run there is refused.
    let again = RunRecord::load(out).is_ok_and(|r| !r.merged_from.is_empty() && r.status != RunStatus::Complete);
    if out.join(RUN_FILE).exists() && !again {
        return Err(InputError::new(
            shown(out),
            "--out already holds a run; give merge a new or empty folder (or the folder of a merge that was interrupted)",
        )
        .into());
    }
    let dir = RunDir::open(out.parent().unwrap_or(Path::new(".")), Some(out), &first.matrix.name, again)?;
    let records: Vec<&RunRecord> = shards.values().map(|(_, r)| r).collect();
    let mut merged = first.clone();
    merged.matrix.shard = None;
    merged.status = RunStatus::Running;
    merged.merged_from = shards.values().map(|(p, _)| shown(p)).collect();
    crate::fsutil::write_json(&dir.root.join(RUN_FILE), &merged)?;
    // Each cell from the shard that owns it; a support copy only where no owner has it.
    let mut placed: HashSet<String> = HashSet::new();
    let mut twins = 0;
    for owners_only in [true, false] {
        for (src, r) in shards.values() {
            let support: HashSet<&str> = r.support.iter().map(|c| c.0.as_str()).collect();
            // The shard's expansion, not whatever folders its cells/ holds.
            let mut ids: Vec<String> = r.cells.iter().map(|c| c.0.clone()).collect();
            ids.sort();
            for id in ids {
                let from = src.join("cells").join(&id);
                if placed.contains(&id) || support.contains(id.as_str()) == owners_only {
                    continue;
                }
                let path = from.join(CELL_FILE);
                // A folder without its record never finished: it is not part of the shard.
                let record = match CellRecord::load(&path) {
                    Ok(r) => r,
                    Err(crate::record::RecordError::Absent) => continue,
                    Err(e) => return Err(e.into_error(&path, "cell record")),
                };
                twins += usize::from(record.twin_of.is_some());
                // A folder left by an interrupted merge into `--out` is replaced; only ever one
                // inside the merged run's cells/ (the id is one path component, and cells/ is
                // the run's own folder, not a link out of it).
                let to = dir.cell_dir(&id);
                crate::record::layout::check_inside(&dir.root, &to)?;
                super::cell_cache::copy_into_place(&from, &to, "merge")?;
                placed.insert(id);
            }
        }
    }

    merged.status = RunStatus::Reporting;
    merged.started = records.iter().map(|r| r.started.clone()).min().unwrap_or_default();
    merged.finished = records.iter().filter_map(|r| r.finished.clone()).max();
    merged.wall_seconds = records.iter().filter_map(|r| r.wall_seconds).reduce(f64::max);
    let sum = |f: fn(&RunRecord) -> usize| records.iter().map(|r| f(r)).sum::<usize>();
    merged.counts.cells = placed.len();
    merged.counts.twins = twins;
    merged.counts.rendered = sum(|r| r.counts.rendered);
    merged.counts.resumed = sum(|r| r.counts.resumed);
    merged.counts.cached = sum(|r| r.counts.cached);
    merged.counts.support = sum(|r| r.counts.support);
    merged.compositions = Vec::new();
    for r in &records {
        for c in &r.compositions {
            if !merged.compositions.iter().any(|m| m.name == c.name) {
                merged.compositions.push(c.clone());
            }
        }
    }
    merged.stages = records.iter().filter_map(|r| r.stages.clone()).reduce(add_stages);
    merged.support = Vec::new();
    let mut cells: Vec<crate::cells::CellId> = placed.iter().cloned().map(crate::cells::CellId).collect();
    cells.sort();
    merged.cells = cells;
    crate::fsutil::write_json(&dir.root.join(RUN_FILE), &merged)?;
    Ok(MergeSummary { dir: dir.root, lock: dir.lock, cells: placed.len(), shards: n })
}

/// Every cell the shard lists is a cell of its recomputed expansion, and every finished one was
/// rendered from the inputs that key says: else refused, naming the cell and the first input
/// that differs.
fn check_against_expansion(matrix: &Matrix, dir: &Path, r: &RunRecord, shard: (u32, u32)) -> Result<(), Error> {
    let shown = dir.join(RUN_FILE).display().to_string();
    let opts = super::runner::RunOptions { shard: Some(shard), only: r.matrix.only.clone(), ..Default::default() };
    let exp = super::runner::select_cells(matrix, &opts);
    let by_id: std::collections::HashMap<&CellId, &crate::cells::Cell> = exp.cells.iter().map(|c| (&c.id, c)).collect();
    let listed: Vec<&crate::cells::Cell> = r.cells.iter().filter_map(|id| by_id.get(id).copied()).collect();
    if let Some(id) = r.cells.iter().find(|id| !by_id.contains_key(id)) {
        return Err(InputError::at_key(
            shown,
            "cells",
            format!(
                "`{id}` is not a cell of shard {}/{} of {} as it expands today: a composition changed since \
                 the shard ran, or the record was edited",
                shard.0, shard.1, matrix.origin
            ),
        )
        .into());
    }
    let keys = super::cell_key::CellKeys::new(matrix, &listed, &r.adapter);
    for c in listed {
        let path = dir.join("cells").join(&c.id.0).join(CELL_FILE);
        let record = match CellRecord::load(&path) {
            Ok(rec) => rec,
            Err(crate::record::RecordError::Absent) => continue,
            Err(e) => return Err(e.into_error(&path, "cell record")),
        };
        let key = keys.get(&c.id);
        if record.input_hash == key {
            continue;
        }
        let now = keys.inputs(&c.id);
        let differs = super::cell_key::KEY_INPUTS
            .iter()
            .find(|(name, _)| record.key_inputs.get(*name) != now.get(*name))
            .map_or("an input its record does not list (a record of an older tool)".to_string(), |(name, what)| {
                format!("{what} (`{name}`)")
            });
        return Err(InputError::at_key(
            path.display().to_string(),
            "input_hash",
            format!(
                "cell `{}` was rendered from other inputs than the matrix reads today: {differs} differs; \
                 render the shard again (`run --shard {}/{} --out {}`)",
                c.id,
                shard.0,
                shard.1,
                dir.display()
            ),
        )
        .into());
    }
    Ok(())
}

/// The adapter as far as timings and images compare: its name, backend and driver.
fn adapter_class(r: &RunRecord) -> String {
    format!("{} ({}, {} {})", r.adapter.name, r.adapter.backend, r.adapter.driver, r.adapter.driver_info)
}

/// `K/N` with 1 ≤ K ≤ N: a label such as `0/0` or `5/3` is no shard.
fn parse_shard(s: &str) -> Option<(u32, u32)> {
    let (k, n) = s.split_once('/')?;
    let (k, n): (u32, u32) = (k.parse().ok()?, n.parse().ok()?);
    (1..=n).contains(&k).then_some((k, n))
}

/// Each cell of the shard's expansion (`RunRecord::cells`) has a finished folder: a record that
/// reads, with its images beside it. A shard missing one does not merge.
fn check_shard_cells(dir: &Path, r: &RunRecord) -> Result<(), Error> {
    let shown = dir.join(RUN_FILE).display().to_string();
    if r.cells.len() != r.counts.cells {
        return Err(InputError::at_key(
            shown,
            "cells",
            format!(
                "lists {} cells, but counts.cells says {}: the record was edited or is of an older tool; \
                 render the shard again",
                r.cells.len(),
                r.counts.cells
            ),
        )
        .into());
    }
    for id in &r.cells {
        let cell = dir.join("cells").join(&id.0);
        let finished = CellRecord::load(&cell.join(CELL_FILE)).is_ok_and(|c| c.id == *id)
            && cell.join("image.exr").is_file()
            && cell.join("image.png").is_file();
        if !finished {
            return Err(InputError::at_key(
                shown,
                "cells",
                format!(
                    "cell `{id}` of this shard is missing or unfinished in {}; continue the shard with \
                     `run --resume --out {}` first",
                    cell.display(),
                    dir.display()
                ),
            )
            .into());
        }
    }
    Ok(())
}

/// Two shards' stage times as one run's: times and CPU summed, the peak the larger.
fn add_stages(a: StageTimes, b: StageTimes) -> StageTimes {
    let both = |x: Maybe<f64>, y: &Maybe<f64>| match (x.value(), y.value()) {
        (Some(p), Some(q)) => Maybe::Value(p + q),
        _ => Maybe::missing("not reported by every shard"),
    };
    let peak = match (a.peak_rss_bytes.value(), b.peak_rss_bytes.value()) {
        (Some(p), Some(q)) => Maybe::Value(*p.max(q)),
        _ => Maybe::missing("not reported by every shard"),
    };
    StageTimes {
        prepare_ms: a.prepare_ms + b.prepare_ms,
        render_ms: a.render_ms + b.render_ms,
        readback_ms: a.readback_ms + b.readback_ms,
        encode_ms: a.encode_ms + b.encode_ms,
        metrics_ms: a.metrics_ms + b.metrics_ms,
        render_blocked_ms: a.render_blocked_ms + b.render_blocked_ms,
        process_cpu: both(a.process_cpu.clone(), &b.process_cpu),
        peak_rss_bytes: peak,
        ..a
    }
}
