//! What `paper` runs: the curves of every table, the spectral predictions
//! and the timing cases, for each mode. Everything here is a pure function of
//! the mode and the seed, so a rerun resolves the same plan and the runner can
//! compare it with the stored one.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::theory::{EdgeCase, Theory};
use crate::experiments::convergence::{self, DirSpec, Row};
use crate::integrand::{IntegrandKind, IntegrandSpec, Params, DEFAULT_RADIUS, DEFAULT_SIGMA};
use crate::sampler::{Sampler, DEFAULT_RELATIVE_RADIUS};
use crate::spec::{Primitive, ShiftMode};

pub use crate::spec::Mode;

/// The tables of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Table {
    /// Rate table: points and unidirectional lines, best and worst case.
    Rates,
    /// Points, segments and lines in 3D: the segment cross-over.
    Segments,
    /// Multi-directional and random-direction lines.
    Directions,
    /// Poisson-disk line offsets against random and jittered offsets.
    Offsets,
    /// Line orientation against a straight edge.
    Edge,
}

impl Table {
    /// The name in `rates.csv`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Table::Rates => "rates",
            Table::Segments => "segments",
            Table::Directions => "directions",
            Table::Offsets => "offsets",
            Table::Edge => "edge",
        }
    }
}

/// A randomised or fixed straight edge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeRun {
    /// How the lines meet the edge.
    pub case: EdgeCase,
    /// `true`: the edge offset `h` is drawn uniformly in `[lo, hi)` per
    /// realisation and the pattern is not shifted; `false`: a fixed edge and
    /// no shift (the pitfall).
    pub randomised: bool,
    pub lo: f64,
    pub hi: f64,
}

/// One convergence curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// Stable identifier (file names).
    pub id: String,
    /// The tables that show it.
    pub tables: Vec<Table>,
    /// The estimator, pattern, N and R.
    pub run: convergence::Config,
    /// A straight-edge run.
    pub edge: Option<EdgeRun>,
}

impl Curve {
    /// The theory of the curve (segments: asymptotic), or `None` where the
    /// rule does not apply (the fixed-edge pitfall).
    #[must_use]
    pub fn theory(&self) -> Option<Theory> {
        let r = &self.run;
        if let Some(e) = self.edge {
            if !e.randomised {
                return None;
            }
        }
        if matches!(r.dirs, DirSpec::Random) {
            // Independent random directions: i.i.d. lines, N^-1.
            return Some(Theory {
                beta: 0.0,
                alpha: f64::NAN,
                pattern_dims: r.pattern_dims(),
                slope: -1.0,
                log_power: 0,
            });
        }
        Some(Theory::of(
            r.sampler,
            r.integrand.kind,
            r.primitive,
            r.dims(),
            self.edge.map(|e| e.case),
        ))
    }

    /// The point-like theory of a segment curve (`N ≪ λ^(−d)`).
    #[must_use]
    pub fn point_theory(&self) -> Theory {
        let r = &self.run;
        Theory::of(
            r.sampler,
            r.integrand.kind,
            Primitive::Points,
            r.dims(),
            None,
        )
    }

    /// The segment cross-over `N* = λ^(−d)` (segments only).
    #[must_use]
    pub fn crossover(&self) -> Option<f64> {
        (self.run.primitive == Primitive::Segments)
            .then(|| self.run.length.powi(-(self.run.dims() as i32)))
    }

    /// `disk 2D, lines, jittered` plus what distinguishes it.
    #[must_use]
    pub fn label(&self) -> String {
        let r = &self.run;
        let mut s = format!(
            "{} {}D, {}",
            r.integrand.kind.name(),
            r.dims(),
            r.primitive.name()
        );
        if r.primitive == Primitive::Segments {
            s.push_str(&format!(" λ = {}", r.length));
        }
        match &r.dirs {
            DirSpec::Groups(k) => s.push_str(&format!(
                ", K = {k} direction group{}",
                if *k == 1 { "" } else { "s" }
            )),
            DirSpec::Random => s.push_str(", random directions"),
            _ => {}
        }
        if let Some(e) = self.edge {
            s.push_str(match (e.case, e.randomised) {
                (EdgeCase::Crossing, _) => ", crossing the edge",
                (EdgeCase::Parallel, true) => ", parallel to the edge",
                (EdgeCase::Parallel, false) => ", parallel, fixed edge",
            });
        }
        s.push_str(&format!(", {}", r.sampler));
        s
    }
}

/// One spectral prediction: the mean periodogram of `sampler` with `n`
/// points in `pattern_dims` dimensions on the grid `[−k, k]^d′`, from
/// `realisations` realisations, and the curves' rows it predicts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    pub sampler: Sampler,
    pub pattern_dims: usize,
    pub n: usize,
    pub k: usize,
    pub realisations: u64,
    /// `(curve, row)` indices.
    pub rows: Vec<(usize, usize)>,
    /// Keep the mean periodogram for the spectrum figures.
    pub figure: bool,
}

/// The timing cases.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// `(integrand, primitive)` cases of the f32 SIMD vs f64 comparison.
    pub simd: Vec<(IntegrandSpec, Primitive)>,
    pub simd_evaluations: usize,
    pub repeats: usize,
    /// NUFFT sweep: dims, N, k, tolerances.
    pub nufft_dims: usize,
    pub nufft_n: usize,
    pub nufft_k: usize,
    pub nufft_tols: Vec<f64>,
}

/// The whole plan (the configuration the runner stores).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub mode: Mode,
    pub seed: u64,
    pub curves: Vec<Curve>,
    pub predictions: Vec<Prediction>,
    pub timing: Timing,
    /// Segment lengths of the cross-over table.
    pub lengths: Vec<f64>,
    /// The sampler, N and λ of the spectrum figures.
    pub figure_n: usize,
    pub figure_length: f64,
}

/// Realisations and sample counts of a mode.
struct Budget {
    /// R for random, jittered, multi-jittered, Sobol'.
    cheap: u64,
    /// R for Poisson disk.
    poisson: u64,
    /// R for CCVT.
    ccvt: u64,
    /// R cap for lines and segments in 3D, and in 2D (the exact `f64`
    /// integrals along a line or segment cost 0.3–6 µs, against about 10 ns
    /// for a point).
    costly: u64,
    costly_2d: u64,
    /// Smallest and largest N per pattern dimension d′ = 1, 2, 3.
    min_n: [usize; 3],
    max_n: [usize; 3],
    /// Take every `sobol_step`-th N of the lists (1: every one).
    sobol_step: usize,
    /// Largest N of CCVT per d′ = 2, 3.
    ccvt_max: [usize; 2],
    /// Largest N of Poisson disk per d′ = 1, 2, 3.
    poisson_max: [usize; 3],
    /// Periodogram realisations (cheap samplers; Poisson disk and CCVT a quarter).
    pred: u64,
}

impl Budget {
    fn of(mode: Mode) -> Self {
        match mode {
            Mode::Quick => Budget {
                cheap: 2048,
                poisson: 128,
                ccvt: 128,
                costly: 256,
                costly_2d: 1024,
                min_n: [16, 16, 8],
                max_n: [4096, 4096, 4096],
                sobol_step: 1,
                ccvt_max: [1024, 512],
                poisson_max: [4096, 4096, 4096],
                pred: 64,
            },
            Mode::Full => Budget {
                cheap: 8192,
                poisson: 512,
                ccvt: 256,
                costly: 1024,
                costly_2d: 2048,
                min_n: [16, 16, 8],
                max_n: [16384, 16384, 32768],
                sobol_step: 1,
                ccvt_max: [4096, 1331],
                poisson_max: [16384, 16384, 8192],
                pred: 256,
            },
            Mode::Reduced => Budget {
                cheap: 512,
                poisson: 64,
                ccvt: 16,
                costly: 128,
                costly_2d: 512,
                min_n: [16, 16, 8],
                max_n: [1024, 1024, 512],
                sobol_step: 2,
                ccvt_max: [256, 64],
                poisson_max: [1024, 1024, 512],
                pred: 32,
            },
        }
    }

    fn realisations(&self, s: Sampler, primitive: Primitive, dims: usize) -> u64 {
        let r = match s {
            Sampler::PoissonDisk | Sampler::PoissonDiskThinned => self.poisson,
            Sampler::Ccvt => self.ccvt,
            _ => self.cheap,
        };
        match (dims, primitive) {
            (_, Primitive::Points) => r,
            (3, _) => r.min(self.costly),
            _ => r.min(self.costly_2d),
        }
    }

    /// The N of `s` in `d′` dimensions: powers of two for Owen-Sobol′ and PMJ02 (their
    /// net properties need `N = 2^m`), `m^d′` for the others (jittered needs
    /// whole strata; the rest use the same N so that rows compare), capped at
    /// the mode's largest N (and CCVT's).
    fn ns(&self, s: Sampler, pattern_dims: usize) -> Vec<usize> {
        let max = self.max_n[pattern_dims - 1];
        let max = match (s, pattern_dims) {
            (Sampler::Ccvt, 2 | 3) => max.min(self.ccvt_max[pattern_dims - 2]),
            (Sampler::PoissonDisk | Sampler::PoissonDiskThinned, _) => {
                max.min(self.poisson_max[pattern_dims - 1])
            }
            _ => max,
        };
        let min = self.min_n[pattern_dims - 1];
        let v: Vec<usize> = if matches!(s, Sampler::Sobol | Sampler::Pmj02) || pattern_dims == 1 {
            (0..63)
                .map(|k| 1usize << k)
                .filter(|&n| n >= min && n <= max)
                .step_by(self.sobol_step)
                .collect()
        } else {
            ROOTS
                .iter()
                .map(|&m| m.pow(pattern_dims as u32))
                .filter(|&n| n >= min && n <= max)
                .step_by(self.sobol_step)
                .collect()
        };
        v
    }
}

/// Side lengths of the jittered grids: about two per octave.
const ROOTS: [usize; 14] = [2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181];

/// The largest N a prediction covers per d′, and its grid `k` (about twice the
/// pattern's Nyquist-like radius `N^(1/d′)`, so that the spectrum outside the
/// grid is white to a good approximation).
fn prediction_grid(pattern_dims: usize, n: usize) -> Option<usize> {
    match pattern_dims {
        1 => (n <= 1024).then(|| (4 * n).max(64)),
        2 => (n <= 1024).then_some(64),
        3 => (n <= 512).then_some(16),
        _ => None,
    }
}

/// The default Gaussian, or disk/ball, of `dims` dimensions (the straight
/// edge builds its own spec).
fn spec(kind: IntegrandKind, dims: usize) -> IntegrandSpec {
    let params = match kind {
        IntegrandKind::Gaussian => Params::Gaussian {
            sigma: DEFAULT_SIGMA,
        },
        _ => Params::Ball {
            radius: DEFAULT_RADIUS,
        },
    };
    IntegrandSpec { kind, dims, params }
}

fn worst(dims: usize) -> IntegrandKind {
    if dims == 2 {
        IntegrandKind::Disk
    } else {
        IntegrandKind::Ball
    }
}

fn axis(dims: usize, a: usize) -> DirSpec {
    let mut v = vec![0.0; dims];
    v[a] = 1.0;
    DirSpec::Fixed(v)
}

struct Builder {
    seed: u64,
    curves: Vec<Curve>,
    index: BTreeMap<String, usize>,
}

impl Builder {
    /// Adds a curve (or adds `table` to the identical one already there).
    #[allow(clippy::too_many_arguments)]
    fn add(
        &mut self,
        table: Table,
        integrand: IntegrandSpec,
        primitive: Primitive,
        sampler: Sampler,
        length: f64,
        dirs: DirSpec,
        ns: &[usize],
        realisations: u64,
        edge: Option<EdgeRun>,
    ) {
        let dims = integrand.dims;
        let groups = match dirs {
            DirSpec::Groups(k) => k,
            _ => 1,
        };
        let mut id = format!("{}-{}d-{}", integrand.kind.name(), dims, primitive.name());
        if primitive == Primitive::Segments {
            id.push_str(&format!("-{length}"));
        }
        match &dirs {
            DirSpec::Groups(k) => id.push_str(&format!("-k{k}")),
            DirSpec::Random => id.push_str("-random-dir"),
            _ => {}
        }
        if let Some(e) = edge {
            id.push_str(match (e.case, e.randomised) {
                (EdgeCase::Crossing, _) => "-crossing",
                (EdgeCase::Parallel, true) => "-parallel",
                (EdgeCase::Parallel, false) => "-parallel-fixed",
            });
        }
        id.push_str(&format!("-{sampler}"));
        if let Some(&i) = self.index.get(&id) {
            if !self.curves[i].tables.contains(&table) {
                self.curves[i].tables.push(table);
            }
            return;
        }
        let rows = ns
            .iter()
            .map(|&n| Row {
                requested: n,
                per_group: n / groups,
                n,
            })
            .collect();
        let shift = if edge.is_some() {
            ShiftMode::None
        } else {
            ShiftMode::Random
        };
        let pattern_dims = if primitive == Primitive::Lines {
            dims - 1
        } else {
            dims
        };
        let run = convergence::Config {
            integrand,
            primitive,
            sampler,
            relative_radius: if sampler.is_poisson() {
                poisson_radius(pattern_dims)
            } else {
                DEFAULT_RELATIVE_RADIUS
            },
            bridson: false,
            length,
            dirs,
            rows,
            realisations,
            seed: self.seed,
            shift,
            notes: Vec::new(),
        };
        self.index.insert(id.clone(), self.curves.len());
        self.curves.push(Curve {
            id,
            tables: vec![table],
            run,
            edge,
        });
    }
}

/// Poisson-disk radius relative to the densest packing (maximal dart
/// throwing): 0.5 in 1D, where a maximal set of radius `r` has gaps below
/// `2r` and so always holds at least `N` points; 0.7 in 2D and 3D, where a
/// maximal set holds about `N` points on average but fewer in some
/// realisations at small `N` (at 0.75, 7 of 8 points fit in one of 2048
/// realisations in 2D; at 0.7 every one of 2048 realisations at each `N` in
/// 8–256, 2D and 3D, fits).
#[must_use]
pub fn poisson_radius(pattern_dims: usize) -> f64 {
    if pattern_dims == 1 {
        0.5
    } else {
        0.7
    }
}

/// The samplers of the rate table whose `d′`-dimensional pattern exists.
fn rate_samplers(pattern_dims: usize) -> Vec<Sampler> {
    [
        Sampler::Random,
        Sampler::Jittered,
        Sampler::PoissonDisk,
        Sampler::Ccvt,
        Sampler::MultiJittered,
        Sampler::Sobol,
        Sampler::Pmj02,
    ]
    .into_iter()
    .filter(|s| s.dims().contains(&pattern_dims))
    .collect()
}

/// The plan of `mode`: the curves of each table, in this order (their
/// indices are the cells' order), then the predictions and the timing.
#[must_use]
pub fn plan(mode: Mode, seed: u64) -> Config {
    let b = Budget::of(mode);
    let mut c = Builder {
        seed,
        curves: Vec::new(),
        index: BTreeMap::new(),
    };
    let reduced = mode == Mode::Reduced;
    let lengths = if reduced {
        vec![0.1, 1.0]
    } else {
        vec![0.001, 0.01, 0.1, 0.4, 1.0]
    };
    add_rate_curves(&mut c, &b, reduced);
    add_segment_curves(&mut c, &b, &lengths);
    add_direction_curves(&mut c, &b);
    add_offset_curves(&mut c, &b);
    add_edge_curves(&mut c, &b, reduced);
    let curves = c.curves;
    let predictions = predictions(&curves, &b, mode);
    let timing = timing(mode);
    Config {
        mode,
        seed,
        curves,
        predictions,
        timing,
        lengths,
        figure_n: 1024,
        figure_length: 0.1,
    }
}

/// Part 1, the rate tables: points and lines in 2D and 3D, each sampler on
/// a smooth and the worst integrand.
fn add_rate_curves(c: &mut Builder, b: &Budget, reduced: bool) {
    for dims in [2, 3] {
        for prim in [Primitive::Points, Primitive::Lines] {
            let pd = if prim == Primitive::Lines {
                dims - 1
            } else {
                dims
            };
            let samplers = if reduced {
                vec![Sampler::Random, Sampler::Jittered]
            } else {
                rate_samplers(pd)
            };
            for s in samplers {
                for kind in [IntegrandKind::Gaussian, worst(dims)] {
                    let dirs = if prim == Primitive::Lines {
                        axis(dims, dims - 1)
                    } else {
                        DirSpec::None
                    };
                    c.add(
                        Table::Rates,
                        spec(kind, dims),
                        prim,
                        s,
                        0.1,
                        dirs,
                        &b.ns(s, pd),
                        b.realisations(s, prim, dims),
                        None,
                    );
                }
            }
        }
    }
}

/// Part 2, segments in 3D: points, segments of each length, lines.
fn add_segment_curves(c: &mut Builder, b: &Budget, lengths: &[f64]) {
    for kind in [IntegrandKind::Ball, IntegrandKind::Gaussian] {
        let s = Sampler::Jittered;
        c.add(
            Table::Segments,
            spec(kind, 3),
            Primitive::Points,
            s,
            0.1,
            DirSpec::None,
            &b.ns(s, 3),
            b.realisations(s, Primitive::Points, 3),
            None,
        );
        for &l in lengths {
            c.add(
                Table::Segments,
                spec(kind, 3),
                Primitive::Segments,
                s,
                l,
                axis(3, 2),
                &b.ns(s, 3),
                b.realisations(s, Primitive::Segments, 3),
                None,
            );
        }
        c.add(
            Table::Segments,
            spec(kind, 3),
            Primitive::Lines,
            s,
            0.1,
            axis(3, 2),
            &b.ns(s, 2),
            b.realisations(s, Primitive::Lines, 3),
            None,
        );
    }
}

/// Part 3, direction groups (2D disk, jittered offsets; N divisible by 6 so
/// that K = 1, 2, 3 see the same total N), and random directions.
fn add_direction_curves(c: &mut Builder, b: &Budget) {
    let ns: Vec<usize> = b
        .ns(Sampler::Random, 1)
        .iter()
        .map(|&n| 6 * (n / 4).max(1))
        .collect::<Vec<_>>();
    for k in 1..=3 {
        c.add(
            Table::Directions,
            spec(IntegrandKind::Disk, 2),
            Primitive::Lines,
            Sampler::Jittered,
            0.1,
            DirSpec::Groups(k),
            &ns,
            b.cheap,
            None,
        );
    }
    c.add(
        Table::Directions,
        spec(IntegrandKind::Disk, 2),
        Primitive::Lines,
        Sampler::Jittered,
        0.1,
        DirSpec::Random,
        &ns,
        b.cheap,
        None,
    );
}

/// Part 4, line offsets: random, jittered, Poisson disk (already in the
/// rate table; added to the offsets table).
fn add_offset_curves(c: &mut Builder, b: &Budget) {
    for dims in [2, 3] {
        for s in [Sampler::Random, Sampler::Jittered, Sampler::PoissonDisk] {
            c.add(
                Table::Offsets,
                spec(worst(dims), dims),
                Primitive::Lines,
                s,
                0.1,
                axis(dims, dims - 1),
                &b.ns(s, dims - 1),
                b.realisations(s, Primitive::Lines, dims),
                None,
            );
        }
    }
}

/// Part 5, the straight edge, 2D, jittered 1D offsets. Crossing: normal
/// (0.7, 1), lines along y; parallel: normal (0, 1), lines along x.
fn add_edge_curves(c: &mut Builder, b: &Budget, reduced: bool) {
    // About two N per octave, not powers of two: with a fixed edge, frac(h·N)
    // then jumps about with N (the pitfall).
    let edge_ns: Vec<usize> = ROOTS
        .iter()
        .map(|&m| m * if reduced { 8 } else { 4 })
        .filter(|&n| (16..=1024).contains(&n))
        .collect();
    for (case, normal, dir_axis, randomised, lo, hi) in [
        (EdgeCase::Crossing, vec![0.7, 1.0], 1, true, 0.0, 1.7),
        (EdgeCase::Parallel, vec![0.0, 1.0], 0, true, 0.0, 1.0),
        (EdgeCase::Parallel, vec![0.0, 1.0], 0, false, GOLDEN, GOLDEN),
    ] {
        let integrand = IntegrandSpec {
            kind: IntegrandKind::Edge,
            dims: 2,
            params: Params::Edge { normal, offset: lo },
        };
        c.add(
            Table::Edge,
            integrand,
            Primitive::Lines,
            Sampler::Jittered,
            0.1,
            axis(2, dir_axis),
            &edge_ns,
            b.cheap,
            Some(EdgeRun {
                case,
                randomised,
                lo,
                hi,
            }),
        );
    }
}

/// The fixed edge offset of the pitfall row, `(√5 − 1)/2`: `frac(h·N)`
/// jumps about with N.
pub const GOLDEN: f64 = 0.618_033_988_749_894_9;

/// Whether the spectral prediction applies to a curve: homogenised, one fixed
/// axis direction (or points).
fn predictable(c: &Curve) -> bool {
    c.edge.is_none()
        && c.run.shift == ShiftMode::Random
        && match &c.run.dirs {
            DirSpec::None => true,
            DirSpec::Fixed(v) => v.iter().filter(|&&x| x != 0.0).count() == 1,
            _ => false,
        }
}

fn predictions(curves: &[Curve], b: &Budget, mode: Mode) -> Vec<Prediction> {
    let mut map: BTreeMap<(String, usize, usize), Prediction> = BTreeMap::new();
    for (ci, c) in curves.iter().enumerate() {
        if !predictable(c) {
            continue;
        }
        let pd = c.run.pattern_dims();
        for (ri, row) in c.run.rows.iter().enumerate() {
            let Some(k) = prediction_grid(pd, row.per_group) else {
                continue;
            };
            let s = c.run.sampler;
            let realisations = match s {
                // Poisson disk and CCVT cost 10-1000x more per pattern: a
                // quarter of the realisations above N = 256.
                Sampler::PoissonDisk | Sampler::Ccvt if row.per_group > 256 => (b.pred / 4).max(8),
                _ => b.pred,
            };
            let key = (s.name().to_string(), pd, row.per_group);
            map.entry(key)
                .or_insert_with(|| Prediction {
                    sampler: s,
                    pattern_dims: pd,
                    n: row.per_group,
                    k,
                    realisations,
                    rows: Vec::new(),
                    figure: pd == 2 && row.per_group == 1024
                        || mode == Mode::Reduced && pd == 2 && row.per_group == 256
                        || pd == 1 && row.per_group == 64,
                })
                .rows
                .push((ci, ri));
        }
    }
    map.into_values().collect()
}

fn timing(mode: Mode) -> Timing {
    let simd = if mode == Mode::Reduced {
        vec![(spec(IntegrandKind::Disk, 2), Primitive::Lines)]
    } else {
        let mut v = Vec::new();
        for (kind, dims) in [
            (IntegrandKind::Disk, 2),
            (IntegrandKind::Gaussian, 2),
            (IntegrandKind::Ball, 3),
            (IntegrandKind::Gaussian, 3),
        ] {
            for p in [Primitive::Segments, Primitive::Lines] {
                v.push((spec(kind, dims), p));
            }
        }
        v
    };
    let (simd_evaluations, repeats) = match mode {
        Mode::Reduced => (4096, 3),
        Mode::Quick => (65_536, 7),
        Mode::Full => (262_144, 11),
    };
    let (nufft_n, nufft_k) = match mode {
        Mode::Reduced => (1024, 16),
        Mode::Quick => (4096, 64),
        Mode::Full => (16384, 128),
    };
    Timing {
        simd,
        simd_evaluations,
        repeats,
        nufft_dims: 2,
        nufft_n,
        nufft_k,
        nufft_tols: vec![1e-2, 1e-4, 1e-6, 1e-9, 1e-12],
    }
}
