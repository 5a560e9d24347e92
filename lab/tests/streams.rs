//! One seed scheme for every scene experiment: the streams of every cell of
//! the four shipped scenes' studies (the AO pixel study at both paper
//! pixels, the direct-light study at two pixels with `N` up to 4097 and
//! every estimator, the caustic study in 2D and 3D) and the seeds of their
//! realisations are all distinct, within each study and across them (one
//! paper run holds all of them). The direct-light scene numbered its rows
//! `1000·e + N`, which the same rows make collide.

use std::collections::HashSet;
use std::fs;
use std::path::PathBuf;

use linesample_lab::experiments::{caustic, direct, scene as ao};
use linesample_lab::scene::{self, SceneSampler};
use linesample_lab::streams::Stream;

fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}"))
}

#[test]
fn no_two_cells_or_realisations_share_a_stream() {
    let mut streams: Vec<(Stream, u64)> = Vec::new();
    // AO: the default rows at both paper pixels.
    let path = scene_path("ao-spheres.toml");
    let text = fs::read_to_string(&path).unwrap();
    let sc = scene::parse(&path, &text).unwrap();
    for pixel in [(410, 305), (300, 290)] {
        let cfg = ao::PixelConfig {
            source: ao::SceneSource {
                path: path.display().to_string(),
                text: text.clone(),
            },
            width: 512,
            height: 512,
            pixel,
            seed: 7,
            shift: linesample_lab::cli::ShiftMode::Random,
            ns: vec![16, 64, 256, 1024, 1089, 4096],
            realisations: 64,
            rows: ao::all_rows(&sc),
            reference_lines: 4096,
            reference_realisations: 64,
            spectrum_realisations: 0,
        };
        let study = ao::PixelStudy::new(cfg).unwrap();
        streams.extend(study.streams().into_iter().map(|s| (s, 64)));
    }
    // Direct light: every estimator at two pixels, at squares (jittered
    // points need them) whose old stream numbers collide: 1000·1 + 2025 =
    // 1000·0 + 3025, 1000·1 + 225 = 1225.
    let path = scene_path("cornell-box.toml");
    let text = fs::read_to_string(&path).unwrap();
    let sc = scene::parse(&path, &text).unwrap();
    let estimators = direct::study_estimators(&sc, &[SceneSampler::Random, SceneSampler::Jittered]);
    let ns = vec![1, 16, 225, 1225, 2025, 3025];
    let cfg = direct::PixelConfig {
        source: ao::SceneSource {
            path: path.display().to_string(),
            text,
        },
        width: 512,
        height: 512,
        pixels: vec![("A".into(), 200, 400), ("B".into(), 300, 420)],
        seed: 7,
        ns: ns.clone(),
        realisations: 64,
        estimators: estimators.clone(),
        reference_lines: 4096,
        reference_realisations: 64,
        shift: None,
    };
    let study = direct::PixelStudy::new(cfg).unwrap();
    let dl = study.streams();
    assert_eq!(dl.len(), 2 * (1 + estimators.len() * ns.len()));
    streams.extend(dl.into_iter().map(|s| (s, 64)));
    // The old numbering makes these rows collide.
    let old: Vec<u64> = (0..estimators.len() as u64)
        .flat_map(|e| ns.iter().map(move |&n| 1000 * e + n as u64))
        .collect();
    assert!(
        old.len() > old.iter().collect::<HashSet<_>>().len(),
        "the old numbering should collide for these rows"
    );
    // The caustic study in 2D and 3D.
    for dims in [2, 3] {
        let path = scene_path(&format!("caustic-{dims}d.toml"));
        let text = fs::read_to_string(&path).unwrap();
        let cfg = caustic::StudyConfig {
            source: caustic::CausticSource {
                path: path.display().to_string(),
                text,
            },
            seed: 7,
            ns: vec![16, 64, 1024, 4096],
            realisations: 64,
            rows: caustic::study_rows(&[SceneSampler::Random, SceneSampler::Jittered]),
            reference_beams: 4096,
            reference_realisations: 64,
            shift: None,
        };
        let study = caustic::Study::new(cfg).unwrap();
        streams.extend(study.streams().into_iter().map(|s| (s, 64)));
    }
    let keys: HashSet<Stream> = streams.iter().map(|s| s.0).collect();
    assert_eq!(keys.len(), streams.len(), "two cells share a stream");
    let mut seeds = HashSet::new();
    let mut count = 0usize;
    for (s, r) in &streams {
        for k in 0..*r {
            seeds.insert(s.realisation(7, k).0);
            count += 1;
        }
    }
    assert_eq!(seeds.len(), count, "two realisations share a seed");
    assert!(count > 50_000, "{count}");
}
