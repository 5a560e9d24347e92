//! The scene parts of the report, as one list: each names the folder its
//! runs write under `OUT/`, the runs (images and studies, resumable on
//! their own), and the report section that reads their files. The paper
//! command and the report walk this list; neither names a scene.

use std::path::Path;

use super::plan::Mode;
use super::report;
use crate::experiments::{caustic, direct, scene};
use crate::runner::RunOptions;

/// One scene part of the report.
#[derive(Clone, Copy, Debug)]
pub struct ScenePart {
    /// Its folder under `OUT/`.
    pub dir: &'static str,
    /// Runs its experiments for `mode` and `seed` into `dir`.
    pub run: fn(Mode, u64, &Path, &RunOptions) -> crate::Result<()>,
    /// Its report section, read from `OUT/` (a note saying how to produce
    /// it when the files are missing).
    pub section: fn(&Path, Mode) -> crate::Result<String>,
}

/// The scene parts, in the report's order: ambient occlusion (section 8),
/// direct light (9), volumetric caustics (10).
pub const PARTS: [ScenePart; 3] = [
    ScenePart {
        dir: "ao",
        run: |m, s, d, o| scene::paper_runs(m, s, d, o).map(|_| ()),
        section: report::section_scene,
    },
    ScenePart {
        dir: "direct",
        run: direct::paper_runs,
        section: |d, _| report::section_direct(d),
    },
    ScenePart {
        dir: "caustics",
        run: caustic::paper_runs,
        section: |d, _| report::section_caustics(d),
    },
];

/// The parts' report sections, in [`PARTS`]' order.
#[must_use]
pub fn sections() -> [report::SceneSection; 3] {
    PARTS.map(|p| p.section)
}
