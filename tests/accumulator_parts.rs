//! Export and import of accumulator state (`Periodogram::parts`/`from_parts`,
//! `RunningStats::parts`/`from_parts`), as a run that is resumed or merged from
//! shards computed elsewhere uses them: the round trip is exact (bit for bit,
//! through a fresh buffer), merges of imported state equal merges of the
//! originals, and malformed state is an error naming the parameter.

use linesample::pattern::{Jittered, Pattern};
use linesample::spectrum::{Dft, Grid, Periodogram};
use linesample::stats::RunningStats;
use linesample::{ParamError, Pcg32, Seed, SpectrumError};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// A periodogram of realisations `range` of 8 × 8 jittered points.
fn periodogram(g: Grid<2>, range: std::ops::Range<u64>) -> Periodogram<2, Vec<f64>> {
    let pat = Jittered::new([8, 8]).unwrap();
    let mut dft = Dft::new_vec(g);
    let mut per = Periodogram::new_vec(g);
    let mut scratch = vec![0.0; 16 * Dft::<2, Vec<f64>>::points_scratch_per_sample(g)];
    for r in range {
        let pts = pat.to_vec(Seed::new(3).realization(r)).unwrap();
        dft.clear();
        dft.add_points(&pts, &mut scratch).unwrap();
        per.add(&dft).unwrap();
    }
    per
}

fn means(p: &Periodogram<2, impl AsRef<[f64]> + AsMut<[f64]>>) -> Vec<u64> {
    let mut out = vec![0.0; p.grid().len()];
    p.means(&mut out).unwrap();
    bits(&out)
}

#[test]
fn periodogram_round_trip_is_exact() {
    let g = Grid::<2>::new(10).unwrap();
    let a = periodogram(g, 0..7);
    let b = periodogram(g, 7..12);
    let (state, reals) = a.parts();
    assert_eq!(state.len(), Periodogram::<2, Vec<f64>>::buffer_len(g));
    assert_eq!(reals, 7);
    // Import into a fresh buffer (as from a file): same state, same means.
    let imported = Periodogram::from_parts(g, state.to_vec(), reals).unwrap();
    assert_eq!(bits(imported.parts().0), bits(state));
    assert_eq!(imported.realisations(), 7);
    assert_eq!(means(&imported), means(&a));
    // The buffer itself, without a copy.
    let (buf, n) = a.clone().into_parts();
    assert_eq!((bits(&buf), n), (bits(state), reals));
    // A caller slice longer than needed works too, and is not zeroed.
    let mut long = state.to_vec();
    long.extend([9.0, 9.0]);
    let sliced = Periodogram::from_parts(g, &mut long[..], reals).unwrap();
    assert_eq!(means(&sliced), means(&a));
    // Merging imported shards gives the bits of merging the originals, and of
    // one accumulator fed everything.
    let mut merged = a.clone();
    merged.merge(&b).unwrap();
    let (sb, rb) = b.parts();
    let mut merged_imported = Periodogram::from_parts(g, state.to_vec(), reals).unwrap();
    merged_imported
        .merge(&Periodogram::from_parts(g, sb.to_vec(), rb).unwrap())
        .unwrap();
    assert_eq!(bits(merged_imported.parts().0), bits(merged.parts().0));
    assert_eq!(merged_imported.realisations(), 12);
    assert_eq!(means(&merged_imported), means(&merged));
    // Resuming: keep adding to the imported accumulator.
    let mut resumed = Periodogram::from_parts(g, state.to_vec(), reals).unwrap();
    let pat = Jittered::new([8, 8]).unwrap();
    let mut dft = Dft::new_vec(g);
    let mut scratch = vec![0.0; 16 * Dft::<2, Vec<f64>>::points_scratch_per_sample(g)];
    for r in 7..12 {
        let pts = pat.to_vec(Seed::new(3).realization(r)).unwrap();
        dft.clear();
        dft.add_points(&pts, &mut scratch).unwrap();
        resumed.add(&dft).unwrap();
    }
    assert_eq!(means(&resumed), means(&periodogram(g, 0..12)));
    // An empty accumulator round-trips too.
    let empty = Periodogram::new_vec(g);
    let (s0, r0) = empty.parts();
    let e = Periodogram::from_parts(g, s0.to_vec(), r0).unwrap();
    assert_eq!(e.realisations(), 0);
    assert_eq!(means(&e), means(&empty));
}

#[test]
fn periodogram_import_rejects_malformed_state() {
    let g = Grid::<2>::new(4).unwrap();
    let a = periodogram(g, 0..3);
    let (state, reals) = a.parts();
    let need = state.len();
    let err = Periodogram::from_parts(g, state[..need - 1].to_vec(), reals).unwrap_err();
    assert_eq!(
        err,
        SpectrumError::Length {
            name: "buf",
            expected: need,
            got: need - 1
        }
    );
    for (index, bad) in [
        (0, f64::NAN),
        (need - 1, f64::INFINITY),
        (5, f64::NEG_INFINITY),
    ] {
        let mut v = state.to_vec();
        v[index] = bad;
        let err = Periodogram::from_parts(g, v, reals).unwrap_err();
        assert_eq!(err, SpectrumError::NonFinite { name: "buf", index });
        assert!(
            err.to_string().starts_with(&format!("buf[{index}]")),
            "{err}"
        );
    }
    // A negative per-cell sum (e.g. the halves swapped) is not a state.
    let mut v = state.to_vec();
    v[3] = -1.0;
    let err = Periodogram::from_parts(g, v, reals).unwrap_err();
    assert!(
        matches!(
            err,
            SpectrumError::Param(ParamError::OutOfRange { name: "buf", .. })
        ),
        "{err}"
    );
    // Non-zero sums with no realisations.
    let err = Periodogram::from_parts(g, state.to_vec(), 0).unwrap_err();
    assert!(
        matches!(
            err,
            SpectrumError::Param(ParamError::Count {
                name: "realisations",
                ..
            })
        ),
        "{err}"
    );
    assert!(err.to_string().contains("realisations"), "{err}");
}

fn stats_of(xs: &[f64]) -> RunningStats {
    let mut s = RunningStats::new();
    xs.iter().for_each(|&x| s.push(x));
    s
}

fn stat_bits(s: &RunningStats) -> (u64, [u64; 4]) {
    let (n, m) = s.parts();
    (n, m.map(f64::to_bits))
}

#[test]
fn running_stats_round_trip_is_exact() {
    let mut rng = Pcg32::new(9, 1);
    let xs: Vec<f64> = (0..1000)
        .map(|_| {
            let u = f64::from(rng.next_u32()) / 4_294_967_296.0;
            3.0 + u * u * u - 0.2 * u
        })
        .collect();
    for split in [0, 1, 2, 5, 333, 999, 1000] {
        let a = stats_of(&xs[..split]);
        let b = stats_of(&xs[split..]);
        let (na, ma) = a.parts();
        let (nb, mb) = b.parts();
        let ia = RunningStats::from_parts(na, ma).unwrap();
        let ib = RunningStats::from_parts(nb, mb).unwrap();
        assert_eq!(stat_bits(&ia), stat_bits(&a), "split {split}");
        assert_eq!(stat_bits(&ib), stat_bits(&b), "split {split}");
        assert_eq!(ia.variance().to_bits(), a.variance().to_bits());
        assert_eq!(
            ia.variance_std_error().to_bits(),
            a.variance_std_error().to_bits()
        );
        // Merging imported stats gives the bits of merging the originals.
        let mut merged = a;
        merged.merge(&b);
        let mut merged_imported = ia;
        merged_imported.merge(&ib);
        assert_eq!(stat_bits(&merged_imported), stat_bits(&merged), "{split}");
        // Resuming an imported run gives the bits of the uninterrupted one.
        let mut resumed = ia;
        xs[split..].iter().for_each(|&x| resumed.push(x));
        assert_eq!(stat_bits(&resumed), stat_bits(&stats_of(&xs)), "{split}");
    }
    let none = RunningStats::from_parts(0, [0.0; 4]).unwrap();
    assert_eq!(none, RunningStats::new());
}

#[test]
fn running_stats_import_rejects_malformed_state() {
    let good = [1.0, 2.0, -0.5, 3.0];
    for (i, name) in ["mean", "m2", "m3", "m4"].into_iter().enumerate() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut m = good;
            m[i] = bad;
            let err = RunningStats::from_parts(5, m).unwrap_err();
            assert_eq!(err, ParamError::NonFinite { name });
            assert!(err.to_string().starts_with(name), "{err}");
        }
    }
    for (i, name) in [(1, "m2"), (3, "m4")] {
        let mut m = good;
        m[i] = -1e-300;
        let err = RunningStats::from_parts(5, m).unwrap_err();
        assert!(
            matches!(err, ParamError::OutOfRange { name: n, .. } if n == name),
            "{err}"
        );
        assert!(err.to_string().starts_with(name), "{err}");
    }
    // M3 may be negative.
    assert!(RunningStats::from_parts(5, good).is_ok());
    // No samples, but moments: the first non-zero value is named.
    let err = RunningStats::from_parts(0, [0.0, 0.0, 2.0, 1.0]).unwrap_err();
    assert!(
        matches!(err, ParamError::OutOfRange { name: "m3", .. }),
        "{err}"
    );
    let err = RunningStats::from_parts(0, [0.5, 0.0, 0.0, 0.0]).unwrap_err();
    assert!(
        matches!(err, ParamError::OutOfRange { name: "mean", .. }),
        "{err}"
    );
}
