//! Writes the raw output stream of the pattern generator ([`linesample::rng::Counter`])
//! to standard output as little-endian `u32` words, forever (until the reader
//! closes the pipe): the input `tools/dieharder.sh` feeds to `dieharder -g 200`.
//!
//! ```text
//! cargo run --release --example counter_stream -- [SEED] [PURPOSE] [FIRST] | dieharder -a -g 200
//! ```
//!
//! `SEED` and `PURPOSE` (default 1 and the purpose of `Random`, 0x52414E44) pick
//! the stream as `Seed::new(SEED).counter(PURPOSE)`; `FIRST` (default 0) is the
//! first output index, e.g. `4294967000` to cross the 2³² boundary early.
//! On exit it prints on standard error how many bytes it wrote.

use std::io::{self, Write};

use linesample::Seed;

fn arg(i: usize, default: u64) -> u64 {
    std::env::args().nth(i).map_or(default, |s| {
        let s = s.trim();
        let v = match s.strip_prefix("0x") {
            Some(h) => u64::from_str_radix(h, 16),
            None => s.parse(),
        };
        v.unwrap_or_else(|_| {
            eprintln!("counter_stream: argument {i} ({s:?}) is not an integer");
            std::process::exit(2)
        })
    })
}

fn main() {
    let key = Seed::new(arg(1, 1)).counter(arg(2, 0x5241_4E44));
    let first = arg(3, 0);
    let mut t = first;
    let out = io::stdout();
    let mut out = out.lock();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        for w in buf.chunks_exact_mut(4) {
            w.copy_from_slice(&key.at(t).to_le_bytes());
            t = t.wrapping_add(1);
        }
        if out.write_all(&buf).is_err() {
            // The reader is done: say how much it read (at most one buffer more).
            let words = t.wrapping_sub(first);
            eprintln!("counter_stream: wrote {} bytes ({words} words)", words * 4);
            return;
        }
    }
}
