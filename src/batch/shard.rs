//! `--shard I/N`: a deterministic 1/N of the inputs, so that one conversion
//! can be spread over the machines of an existing scheduler.
//!
//! An input belongs to shard `1 + h mod N`, where `h` is the first eight bytes
//! (little-endian) of the BLAKE3 hash of its path relative to the folder it
//! was found in (`/`-separated), or of its file name when it was named
//! directly. Membership depends on nothing but that path and `N`: not on the
//! order of the arguments, the machine, or the other inputs, so every input
//! is in exactly one shard of every run with the same `N`.

use std::fmt;
use std::str::FromStr;

/// Shard `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which shard, from 1 to `count`.
    pub index: u64,
    /// How many shards in all.
    pub count: u64,
}

impl Shard {
    /// Whether the input with this shard key belongs to this shard.
    pub fn contains(&self, key: &str) -> bool {
        bucket(key, self.count) + 1 == self.index
    }
}

/// The 0-based shard of `key` among `count`.
pub fn bucket(key: &str, count: u64) -> u64 {
    let h = blake3::hash(key.as_bytes());
    let mut first = [0u8; 8];
    first.copy_from_slice(&h.as_bytes()[..8]);
    u64::from_le_bytes(first) % count.max(1)
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || format!("--shard {s}: expected I/N with 1 <= I <= N, such as 2/8");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u64 = i.trim().parse().map_err(|_| bad())?;
        let count: u64 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_refuses() {
        assert_eq!("2/8".parse::<Shard>().unwrap(), Shard { index: 2, count: 8 });
        for bad in ["0/3", "4/3", "1/0", "x/2", "2", "", "1/2/3", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn every_key_is_in_exactly_one_shard() {
        for count in 1..=7u64 {
            for k in 0..300 {
                let key = format!("dir{}/diagram-{k}.svg", k % 5);
                let shards = (1..=count).filter(|&index| Shard { index, count }.contains(&key)).count();
                assert_eq!(shards, 1, "{key} in {count} shards");
            }
        }
    }

    #[test]
    fn shards_are_roughly_even() {
        // 4000 keys in 4 shards: a fair hash puts about 1000 in each; 800
        // is more than six standard deviations (~27) below that.
        let mut sizes = [0u32; 4];
        for k in 0..4000 {
            sizes[bucket(&format!("maps/{k}.svg"), 4) as usize] += 1;
        }
        assert!(sizes.iter().all(|&s| s > 800), "{sizes:?}");
    }
}
