//! `linesample-lab pixel-error`: the command line to the experiment's typed configuration.

use crate::cli::PixelErrorArgs;
use crate::experiments::pixel_error::{default_out, run, PixelErrorConfig, LOW_BAND};
use crate::io;
use crate::Result;

/// `linesample-lab pixel-error`.
///
/// # Errors
/// A message naming the offending parameter or file.
pub fn main(a: &PixelErrorArgs) -> Result<()> {
    let out = a.out.clone().unwrap_or_else(|| default_out().to_path_buf());
    io::check_folder("--out", &out)?;
    let cfg = PixelErrorConfig {
        width: a.width,
        height: a.height,
        spp: a.spp,
        realizations: a.realizations,
        seed: a.seed,
        out,
    };
    let res = run(&cfg)?;
    let [(zm, zs), (im, is)] = res.low_band;
    crate::out!(
        "{} x {} pixels, {} spp, {} realization(s): mean normalised error power over rings \
         1..={LOW_BAND} ({} frequencies; white noise = 1, ± 1 SE across realizations): \
         ZSobol {zm:.4} ± {zs:.4}, independent per-pixel seeds {im:.4} ± {is:.4}",
        cfg.width,
        cfg.height,
        cfg.spp,
        cfg.realizations,
        res.low_band_frequencies
    );
    for f in &res.files {
        crate::out!("wrote {}", f.display());
    }
    Ok(())
}
