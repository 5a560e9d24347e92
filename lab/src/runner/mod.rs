//! The one runner every experiment uses.
//!
//! An experiment is a list of **cells** (e.g. one N of a convergence curve, a
//! block of spectrum realisations, one gallery pattern). The runner
//!
//! * runs the cells on a `rayon` pool of `--threads` threads (cells at the same
//!   time unless the experiment asks for them one after another); inside a
//!   cell, [`Ctx::map_ordered`] runs fixed chunks of realisations on the same
//!   pool and returns them in chunk order, so a cell merges its chunk
//!   statistics in a fixed order and its result does not depend on the thread
//!   count;
//! * writes every finished cell atomically into the state folder
//!   `OUT.state/` ([`state`]) with its accumulator state, and on a rerun of the
//!   same command skips the cells already there (`--fresh` starts over; a
//!   different configuration is refused): SIGINT (Ctrl-C) or SIGTERM stops
//!   the run within one chunk of realisations, keeping every finished cell
//!   ([`stop`]), and even a kill loses at most the cells in flight;
//! * with `--shard i/n` computes only the cells `c` with `c mod n = i − 1`;
//!   [`merge`] later gathers the shards' cells into one complete state, from
//!   which the experiment writes exactly the files an unsharded run writes
//!   (cells are merged in cell order in both cases);
//! * shows progress on stderr ([`progress`]).

pub mod progress;
pub mod shard;
pub mod state;
pub mod stop;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use linesample::stats::RunningStats;
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

pub use progress::Progress;
pub use shard::Shard;
pub use state::{Manifest, StateDir, Stored};

use crate::{LabError, Result};

/// Largest `--threads`.
pub const MAX_THREADS: usize = 1024;

/// How to run: the options every runner command shares.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Worker threads (default: the available parallelism).
    pub threads: Option<usize>,
    /// No progress bar and no progress lines.
    pub quiet: bool,
    /// Discard the state folder's cells and start over.
    pub fresh: bool,
    /// Compute only this shard's cells.
    pub shard: Option<Shard>,
}

/// What the progress bar and the manifest say about a cell.
#[derive(Clone, Debug)]
pub struct CellInfo {
    /// E.g. `N = 1024`.
    pub label: String,
    /// Work units the cell does (for progress).
    pub work: u64,
}

/// An experiment the runner can run, resume, shard and merge.
pub trait Experiment: Sync {
    /// The configuration stored in the state manifest; a rerun must match it.
    type Config: Serialize + DeserializeOwned + Clone;
    /// One cell's state, stored in its cell file (enough to merge).
    type Cell: Serialize + DeserializeOwned + Send;
    /// Name of the experiment (its subcommand).
    const KIND: &'static str;
    /// What a unit of [`CellInfo::work`] is, e.g. `realisations`.
    const UNIT: &'static str;
    /// Whether cells may run at the same time. `false` runs them one after
    /// another (each may still use the whole pool inside), e.g. so that
    /// timings inside a cell are not disturbed by other cells.
    const PARALLEL_CELLS: bool = true;

    /// Whether cell `index` must run alone: after every other cell, one
    /// exclusive cell at a time (each may still use the whole pool inside), so
    /// that the timings it measures are not disturbed by other cells.
    fn exclusive(&self, index: usize) -> bool {
        let _ = index;
        false
    }

    /// The configuration.
    fn config(&self) -> &Self::Config;
    /// The cells, in order.
    fn cells(&self) -> &[CellInfo];
    /// Computes cell `index`.
    ///
    /// # Errors
    /// A message naming the cell's parameters.
    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<Self::Cell>;
}

/// What a cell may use while it runs.
#[derive(Debug)]
pub struct Ctx<'a> {
    progress: &'a Progress,
}

impl Ctx<'_> {
    /// Reports `work` units done.
    pub fn advance(&self, work: u64) {
        self.progress.advance(work);
    }

    /// Runs `f(0) … f(count − 1)` on the pool and returns the results in index
    /// order (the first error, if any).
    ///
    /// # Errors
    /// The first error of `f`.
    pub fn map_ordered<T: Send>(
        &self,
        count: usize,
        f: impl Fn(usize) -> crate::Result<T> + Sync + Send,
    ) -> crate::Result<Vec<T>> {
        (0..count)
            .into_par_iter()
            .map(|i| {
                stop::check()?;
                f(i)
            })
            .collect()
    }

    /// Realisations `0 … total − 1` of one estimator, in chunks of `chunk`
    /// on the pool (as [`Ctx::map_ordered`]): each chunk makes its scratch
    /// with `init` and calls `one(&mut scratch, r)` for each of its
    /// realisations `r`, reporting progress per chunk. Returns their
    /// statistics, merged in chunk order (the same for any thread count), and
    /// the seconds per estimate (each chunk timed on its own thread).
    ///
    /// The error type `E` is the closures' own: [`LabError`], or a `String`
    /// for code not yet migrated.
    ///
    /// # Errors
    /// The first error of `init` or `one`.
    pub fn realisations<S, E: From<LabError> + Send>(
        &self,
        total: u64,
        chunk: u64,
        init: impl Fn() -> Result<S, E> + Sync + Send,
        one: impl Fn(&mut S, u64) -> Result<f64, E> + Sync + Send,
    ) -> Result<(RunningStats, f64), E> {
        let chunk = chunk.max(1);
        let count = total.div_ceil(chunk) as usize;
        let parts = (0..count).into_par_iter().map(|c| {
            stop::check()?;
            let mut scratch = init()?;
            let mut rs = RunningStats::new();
            let r0 = c as u64 * chunk;
            let r1 = (r0 + chunk).min(total);
            let t = Instant::now();
            for r in r0..r1 {
                rs.push(one(&mut scratch, r)?);
            }
            let secs = t.elapsed().as_secs_f64();
            self.advance(r1 - r0);
            Ok((rs, secs))
        });
        let parts = parts.collect::<Result<Vec<_>, E>>()?;
        let mut all = RunningStats::new();
        let mut secs = 0.0;
        for (rs, t) in &parts {
            all.merge(rs);
            secs += t;
        }
        let per = secs / all.count().max(1) as f64;
        Ok((all, per))
    }
}

/// How a run went.
#[derive(Clone, Debug)]
pub struct RunInfo {
    /// Worker threads used.
    pub threads: usize,
    /// Wall time of this invocation.
    pub wall: Duration,
    /// Cells computed now.
    pub computed: usize,
    /// Cells found in the state folder.
    pub resumed: usize,
    /// Seconds each cell took when it was computed (index order).
    pub cell_seconds: Vec<f64>,
    /// The shard folders a merge read.
    pub merged_from: Vec<PathBuf>,
}

/// The result of [`run`].
#[derive(Debug)]
pub enum Outcome<C> {
    /// Every cell, in order.
    Complete(Vec<C>, RunInfo),
    /// A shard finished its cells; the rest belongs to other shards.
    Shard {
        /// The shard.
        shard: Shard,
        /// Cells this shard holds.
        done: usize,
        /// Cells of the whole run.
        total: usize,
        /// How it went.
        info: RunInfo,
    },
}

/// The worker pool for `threads` (default: the available parallelism).
///
/// # Errors
/// [`LabError::Usage`] if `threads` is 0 or above [`MAX_THREADS`], or a
/// message if the threads cannot start.
pub fn pool(threads: Option<usize>) -> Result<(rayon::ThreadPool, usize)> {
    let t = threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from));
    if t == 0 || t > MAX_THREADS {
        return Err(LabError::Usage(format!(
            "--threads {t}: expected 1 to {MAX_THREADS}"
        )));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .thread_name(|i| format!("linesample-lab-{i}"))
        .build()
        .map_err(|e| {
            LabError::Usage(format!(
                "--threads {t}: cannot start the worker threads: {e}"
            ))
        })?;
    Ok((pool, t))
}

/// The command line of this process, for manifests.
#[must_use]
pub fn command_line() -> String {
    let mut args = std::env::args();
    let mut s = String::from("linesample-lab");
    args.next();
    for a in args {
        s.push(' ');
        if a.is_empty() || a.contains(|c: char| c.is_whitespace() || "'\"$`\\".contains(c)) {
            s.push('\'');
            s.push_str(&a.replace('\'', r"'\''"));
            s.push('\'');
        } else {
            s.push_str(&a);
        }
    }
    s
}

/// Runs (or resumes) `exp` with its state in `OUT.state` (see the module
/// docs). Prints one line on stdout when it resumes or when a shard is done
/// (unless `quiet`).
///
/// # Errors
/// A changed configuration in the state folder, a locked folder, an I/O
/// error, the first error of a cell, or [`LabError::Stopped`] after SIGINT or
/// SIGTERM.
pub fn run<E: Experiment>(exp: &E, out: &Path, opts: &RunOptions) -> Result<Outcome<E::Cell>> {
    let start = Instant::now();
    let (pool, threads) = pool(opts.threads)?;
    let cells = exp.cells();
    let total = cells.len();
    let mine: Vec<usize> = (0..total)
        .filter(|&c| opts.shard.is_none_or(|s| s.owns(c)))
        .collect();
    let dir = StateDir::open(out)?;
    if opts.fresh {
        dir.clear()?;
    }
    let manifest = Manifest::new(
        E::KIND,
        total,
        opts.shard,
        command_line(),
        exp.config().clone(),
    );
    check_or_write_manifest(&dir, &manifest)?;
    let mut have: BTreeMap<usize, Stored<E::Cell>> = stored_cells(&dir, &mine, opts.quiet)?;
    let resumed = have.len();
    let todo: Vec<usize> = mine
        .iter()
        .copied()
        .filter(|i| !have.contains_key(i))
        .collect();
    if resumed > 0 && !opts.quiet {
        crate::out!(
            "resuming from {}: {resumed} of {} cell(s) already done, computing {}",
            dir.path().display(),
            mine.len(),
            todo.len()
        );
    }
    let work: u64 = todo.iter().map(|&i| cells[i].work).sum();
    let progress = Progress::new(work, E::UNIT, mine.len(), resumed, !opts.quiet);
    let one = |i: usize| -> Result<Stored<E::Cell>> {
        stop::check()?;
        let t = Instant::now();
        let cell = exp.run_cell(
            i,
            &Ctx {
                progress: &progress,
            },
        )?;
        let stored = Stored {
            index: i as u64,
            seconds: t.elapsed().as_secs_f64(),
            cell,
        };
        dir.write_cell(&stored)?;
        progress.cell_done();
        Ok(stored)
    };
    let computed = pool.install(|| each_cell(exp, &todo, one));
    progress.finish();
    let computed = match computed {
        Ok(c) => c,
        Err(_) if stop::requested().is_some() => {
            return Err(LabError::Stopped {
                signal: stop::requested().unwrap_or_default(),
                stored: dir.cell_indices().map_or(0, |v| v.len()),
                cells: mine.len(),
                state: dir.path().to_path_buf(),
            });
        }
        Err(e) => {
            // A first run that failed before any cell leaves no state behind,
            // so that a corrected command is not refused as a "different run".
            if resumed == 0 && dir.cell_indices().is_ok_and(|v| v.is_empty()) {
                dir.remove();
            }
            return Err(e);
        }
    };
    let n_computed = computed.len();
    for s in computed {
        have.insert(s.index as usize, s);
    }
    let info = RunInfo {
        threads,
        wall: start.elapsed(),
        computed: n_computed,
        resumed,
        cell_seconds: have.values().map(|s| s.seconds).collect(),
        merged_from: Vec::new(),
    };
    match opts.shard {
        Some(shard) => Ok(Outcome::Shard {
            shard,
            done: have.len(),
            total,
            info,
        }),
        None => Ok(Outcome::Complete(
            have.into_values().map(|s| s.cell).collect(),
            info,
        )),
    }
}

/// Checks the state folder's manifest against `manifest` (this run's), or
/// writes it into a folder that has none (and no cells).
fn check_or_write_manifest<C: Serialize>(dir: &StateDir, manifest: &Manifest<C>) -> Result<()> {
    match dir.read_manifest()? {
        Some(stored) => state::check_manifest(&stored, manifest, dir.path())?,
        None => {
            if !dir.cell_indices()?.is_empty() {
                return Err(LabError::Message(format!(
                    "{} holds cells but no manifest; use --fresh to start over",
                    dir.path().display()
                )));
            }
            dir.write_manifest(manifest)?;
        }
    }
    Ok(())
}

/// The cells already in the state folder, by index; each must be one of
/// `mine`. A cell that does not decode (e.g. after a power loss) is left out
/// to be computed again, with a note unless `quiet`.
fn stored_cells<C: DeserializeOwned>(
    dir: &StateDir,
    mine: &[usize],
    quiet: bool,
) -> Result<BTreeMap<usize, Stored<C>>> {
    let mut have = BTreeMap::new();
    for i in dir.cell_indices()? {
        if !mine.contains(&i) {
            return Err(LabError::Message(format!(
                "{}: cell {i} does not belong to this run; use --fresh to start over",
                dir.cell_path(i).display()
            )));
        }
        match dir.read_cell(i) {
            Ok(stored) => {
                have.insert(i, stored);
            }
            // A damaged cell (e.g. after a power loss) is computed again.
            Err(e) => {
                if !quiet {
                    crate::err!("note: {e}: computing it again");
                }
            }
        }
    }
    Ok(have)
}

/// Reads the manifest of the state folder of `out` without locking it.
///
/// # Errors
/// If there is no readable manifest.
pub fn read_manifest_json(out: &Path) -> Result<serde_json::Value> {
    let dir = state::state_path(out);
    state::read_manifest_at(&dir)?.ok_or_else(|| {
        LabError::Message(format!(
            "{}: {} has no manifest; is it the --out of a sharded run?",
            out.display(),
            dir.display()
        ))
    })
}

/// Gathers the cells of the shard runs whose `--out` were `shards` into a
/// complete state folder for `out` and returns them in order.
///
/// Every shard must have been run with the same experiment, configuration
/// and shard count, and hold all of its cells; each cell must come from the
/// one shard that owns it.
///
/// # Errors
/// A message naming the shard and what is wrong (different configuration,
/// shard given twice, missing cells and which shard must be rerun).
pub fn merge<E: Experiment>(
    exp: &E,
    out: &Path,
    shards: &[PathBuf],
) -> Result<(Vec<E::Cell>, RunInfo)> {
    let start = Instant::now();
    let total = exp.cells().len();
    // Check every shard before writing anything.
    let mut seen: Vec<(Shard, &PathBuf)> = Vec::new();
    for path in shards {
        let stored = read_manifest_json(path)?;
        let shard: Shard = serde_json::from_value::<Option<Shard>>(
            stored.get("shard").cloned().unwrap_or_default(),
        )
        .map_err(|e| LabError::Message(format!("{}: the manifest's shard: {e}", path.display())))?
        .ok_or_else(|| {
            LabError::Usage(format!(
                "{}: not a sharded run (it was run without --shard)",
                path.display()
            ))
        })?;
        let expected = Manifest::new(
            E::KIND,
            total,
            Some(shard),
            String::new(),
            exp.config().clone(),
        );
        state::check_manifest(&stored, &expected, &state::state_path(path))
            .map_err(|e| LabError::Message(format!("{}: {e}", path.display())))?;
        if let Some((first, _)) = seen.first() {
            if first.count != shard.count {
                return Err(LabError::Usage(format!(
                    "{}: shard {shard}, but the first shard was one of {}",
                    path.display(),
                    first.count
                )));
            }
        }
        if seen.iter().any(|(s, _)| *s == shard) {
            return Err(LabError::Usage(format!(
                "{}: shard {shard} is given twice",
                path.display()
            )));
        }
        seen.push((shard, path));
    }
    let n = seen.first().map_or(0, |(s, _)| s.count);
    let missing: Vec<String> = (1..=n)
        .filter(|&i| !seen.iter().any(|(s, _)| s.index == i))
        .map(|i| format!("{i}/{n}"))
        .collect();
    if !missing.is_empty() || shards.is_empty() {
        return Err(LabError::Usage(format!(
            "merge needs every shard of the run; missing: {}",
            if missing.is_empty() {
                "all".to_string()
            } else {
                missing.join(", ")
            }
        )));
    }
    for &(shard, path) in &seen {
        let dir = state::state_path(path);
        for i in (0..total).filter(|&c| shard.owns(c)) {
            if !state::cell_file(&dir, i).is_file() {
                return Err(LabError::Message(format!(
                    "{}: shard {shard} has not finished cell {i} ({}); rerun that shard's \
                     command to complete it",
                    path.display(),
                    exp.cells()[i].label
                )));
            }
        }
    }
    // Copy cell by cell (each decoded to check it), then read them in order.
    let dir = StateDir::open(out)?;
    let manifest = Manifest::new(E::KIND, total, None, command_line(), exp.config().clone());
    match dir.read_manifest()? {
        Some(stored) => state::check_manifest(&stored, &manifest, dir.path())?,
        None => dir.write_manifest(&manifest)?,
    }
    for &(shard, path) in &seen {
        let from = state::state_path(path);
        for i in (0..total).filter(|&c| shard.owns(c)) {
            let p = state::cell_file(&from, i);
            let b = state::read_file(&p)?;
            state::decode_cell::<E::Cell>(&b, &p, i).map_err(|e| {
                LabError::Message(format!(
                    "{e}; rerun shard {shard} (it recomputes the cell) and merge again"
                ))
            })?;
            dir.write_cell_bytes(i, &b)?;
        }
    }
    let mut cells = Vec::with_capacity(total);
    let mut seconds = Vec::with_capacity(total);
    for i in 0..total {
        let stored: Stored<E::Cell> = dir.read_cell(i)?;
        cells.push(stored.cell);
        seconds.push(stored.seconds);
    }
    Ok((
        cells,
        RunInfo {
            threads: 1,
            wall: start.elapsed(),
            computed: 0,
            resumed: total,
            cell_seconds: seconds,
            merged_from: shards.to_vec(),
        },
    ))
}

/// Computes every cell of `exp` in memory on `threads` threads (no state
/// folder, no progress): for callers that compose results themselves, and for
/// tests. The cells are the same as [`run`] computes.
///
/// # Errors
/// A bad thread count or the first error of a cell.
pub fn compute<E: Experiment>(exp: &E, threads: Option<usize>) -> Result<Vec<E::Cell>> {
    let (pool, _) = pool(threads)?;
    let progress = Progress::new(0, E::UNIT, exp.cells().len(), 0, false);
    let ctx = Ctx {
        progress: &progress,
    };
    let all: Vec<usize> = (0..exp.cells().len()).collect();
    pool.install(|| each_cell(exp, &all, |i| exp.run_cell(i, &ctx)))
}

/// `f` on every cell of `indices`: the shared cells in parallel (unless `E`
/// asks for its cells one after another), then the exclusive ones
/// ([`Experiment::exclusive`]) one at a time; the results in the order of
/// `indices` (the first error, if any). Call it inside the pool.
fn each_cell<E: Experiment, T: Send>(
    exp: &E,
    indices: &[usize],
    f: impl Fn(usize) -> Result<T> + Sync + Send,
) -> Result<Vec<T>> {
    // (position in `indices`, cell index), split into exclusive and shared.
    type Cells = Vec<(usize, usize)>;
    let (alone, shared): (Cells, Cells) = indices
        .iter()
        .copied()
        .enumerate()
        .partition(|&(_, i)| exp.exclusive(i));
    let run = |&(pos, i): &(usize, usize)| f(i).map(|t| (pos, t));
    let mut done: Vec<(usize, T)> = if E::PARALLEL_CELLS {
        shared.par_iter().map(run).collect::<Result<_, _>>()?
    } else {
        shared.iter().map(run).collect::<Result<_, _>>()?
    };
    for cell in &alone {
        done.push(run(cell)?);
    }
    done.sort_by_key(|d| d.0);
    Ok(done.into_iter().map(|(_, t)| t).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// Five cells; cells 1 and 3 are exclusive; each records when it starts
    /// and ends and how many cells were running at that moment.
    struct Toy {
        cells: Vec<CellInfo>,
        log: Mutex<Vec<(usize, usize)>>,
        running: Mutex<usize>,
    }

    impl Experiment for Toy {
        type Config = u8;
        type Cell = usize;
        const KIND: &'static str = "toy";
        const UNIT: &'static str = "units";

        fn exclusive(&self, index: usize) -> bool {
            index % 2 == 1 && index < 4
        }

        fn config(&self) -> &u8 {
            &0
        }

        fn cells(&self) -> &[CellInfo] {
            &self.cells
        }

        fn run_cell(&self, index: usize, _: &Ctx<'_>) -> crate::Result<usize> {
            let others = {
                let mut r = self
                    .running
                    .lock()
                    .map_err(|e| crate::LabError::Message(e.to_string()))?;
                *r += 1;
                *r - 1
            };
            std::thread::sleep(Duration::from_millis(20));
            self.log
                .lock()
                .map_err(|e| crate::LabError::Message(e.to_string()))?
                .push((index, others));
            *self
                .running
                .lock()
                .map_err(|e| crate::LabError::Message(e.to_string()))? -= 1;
            Ok(index * 10)
        }
    }

    #[test]
    fn exclusive_cells_run_alone_after_the_others_and_results_keep_their_order() {
        let toy = Toy {
            cells: (0..5)
                .map(|i| CellInfo {
                    label: format!("{i}"),
                    work: 1,
                })
                .collect(),
            log: Mutex::new(Vec::new()),
            running: Mutex::new(0),
        };
        let cells = compute(&toy, Some(4)).unwrap();
        assert_eq!(cells, vec![0, 10, 20, 30, 40]);
        let log = toy.log.into_inner().unwrap();
        let order: Vec<usize> = log.iter().map(|x| x.0).collect();
        // The three shared cells first (in any order), then 1 and 3 in order.
        assert_eq!(&order[3..], &[1, 3], "{order:?}");
        for &(i, others) in &log {
            if i == 1 || i == 3 {
                assert_eq!(others, 0, "exclusive cell {i} overlapped another");
            }
        }
    }
}
