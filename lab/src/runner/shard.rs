//! `--shard i/n`: a deterministic subset of the cells, by cell index.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::{LabError, Result};

/// Shard `index` of `count` (1-based): the cells whose index `c` has
/// `c mod count = index − 1`. The shards of one `count` partition the cells,
/// whatever their number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "RawShard")]
pub struct Shard {
    /// 1-based shard number.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

/// A shard as stored, checked by [`Shard::new`] when read back.
#[derive(Deserialize)]
struct RawShard {
    index: usize,
    count: usize,
}

impl TryFrom<RawShard> for Shard {
    type Error = LabError;

    fn try_from(r: RawShard) -> Result<Self> {
        Shard::new(r.index, r.count)
    }
}

impl Shard {
    /// Shard `index` of `count`.
    ///
    /// # Errors
    /// [`LabError::Usage`] unless `1 ≤ index ≤ count`.
    pub fn new(index: usize, count: usize) -> Result<Self> {
        if index == 0 || count == 0 || index > count {
            return Err(LabError::Usage(format!(
                "{index}/{count} is not I/N with 1 <= I <= N"
            )));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard computes cell `cell`.
    #[must_use]
    pub fn owns(&self, cell: usize) -> bool {
        cell % self.count == self.index - 1
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = LabError;

    fn from_str(s: &str) -> Result<Self> {
        let bad = || {
            LabError::Usage(format!(
                "expected I/N with 1 <= I <= N, e.g. 2/8 (got '{s}'); in a Slurm job array use \
                 $((SLURM_ARRAY_TASK_ID+1))/$SLURM_ARRAY_TASK_COUNT"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        Shard::new(index, count).map_err(|_| bad())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_partitions() {
        assert_eq!(
            "2/3".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 3 }
        );
        for bad in ["0/3", "4/3", "1", "a/b", "1/0", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        let shards: Vec<Shard> = (1..=3).map(|i| Shard { index: i, count: 3 }).collect();
        for c in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.owns(c)).count(), 1);
        }
        assert_eq!(Shard { index: 2, count: 3 }.to_string(), "2/3");
        // A stored shard is checked when it is read back.
        let bad: Result<Shard, _> = serde_json::from_str(r#"{"index":0,"count":0}"#);
        assert!(bad.unwrap_err().to_string().contains("not I/N"));
    }
}
