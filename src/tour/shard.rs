//! Sharding a tour across processes: `I/N` given, or read from the batch scheduler's
//! environment (Slurm job arrays, Kubernetes Indexed Jobs, GNU parallel). Shard `i` of `n`
//! renders frames `floor(i*N/n) .. floor((i+1)*N/n) - 1` (DESIGN §10).

use std::fmt;
use std::ops::Range;
use std::str::FromStr;

/// One shard: the `index`-th (from 0) of `count` contiguous, balanced frame ranges.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// From 0.
    pub index: u32,
    /// At least 1.
    pub count: u32,
}

impl Shard {
    /// The whole tour.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// A shard, checked: `count >= 1` and `index < count`.
    pub fn new(index: u32, count: u32) -> Result<Shard, String> {
        if count == 0 {
            return Err("the shard count must be at least 1".into());
        }
        if index >= count {
            return Err(format!(
                "shard index {index} is out of range for {count} shards (0..={})",
                count - 1
            ));
        }
        Ok(Shard { index, count })
    }

    /// The frames of this shard among `frames`.
    pub fn frames(&self, frames: usize) -> Range<usize> {
        let at = |i: u32| (i as u128 * frames as u128 / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `--shard`: `I/N` or `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShardChoice {
    /// Given on the command line.
    Given(Shard),
    /// From the scheduler's environment.
    Auto,
}

impl FromStr for ShardChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("auto") {
            return Ok(ShardChoice::Auto);
        }
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("expected I/N (e.g. 0/4) or auto, got `{s}`"))?;
        let number = |t: &str| {
            t.trim()
                .parse::<u32>()
                .map_err(|_| format!("`{t}` is not a whole number in `{s}` (expected I/N)"))
        };
        Shard::new(number(i)?, number(n)?).map(ShardChoice::Given)
    }
}

/// Which scheduler `--shard auto` took its shard from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShardSource {
    /// `SLURM_ARRAY_TASK_ID`, `SLURM_ARRAY_TASK_MIN`, `SLURM_ARRAY_TASK_COUNT`.
    Slurm,
    /// `JOB_COMPLETION_INDEX` with `--shards N`.
    Kubernetes,
    /// `PARALLEL_SEQ` (1-based) with `--shards N`.
    GnuParallel,
}

impl fmt::Display for ShardSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ShardSource::Slurm => "Slurm job array (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of SLURM_ARRAY_TASK_COUNT)",
            ShardSource::Kubernetes => "Kubernetes Indexed Job (JOB_COMPLETION_INDEX)",
            ShardSource::GnuParallel => "GNU parallel (PARALLEL_SEQ - 1)",
        })
    }
}

/// Reads the shard from the scheduler's variables, looked up through `var`: Slurm first, then
/// a Kubernetes Indexed Job, then GNU parallel. `shards` (`--shards N`) gives the count the
/// latter two lack; with Slurm it must agree with the array's task count when given.
pub fn from_environment(
    var: impl Fn(&str) -> Option<String>,
    shards: Option<u32>,
) -> Result<(Shard, ShardSource), String> {
    let number = |name: &str| -> Result<Option<u64>, String> {
        match var(name) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse::<u64>()
                .map(Some)
                .map_err(|_| format!("{name}=`{v}` is not a whole number")),
        }
    };
    let count_of = |name: &str| -> Result<u32, String> {
        shards.ok_or_else(|| format!("{name} is set but the shard count is not: pass --shards N"))
    };
    let index_u32 = |i: u64, what: &str| {
        u32::try_from(i).map_err(|_| format!("{what} {i} is too large for a shard index"))
    };
    if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let step = number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
        let count = match (number("SLURM_ARRAY_TASK_COUNT")?, shards) {
            (Some(c), Some(s)) if c != u64::from(s) => {
                return Err(format!(
                    "SLURM_ARRAY_TASK_COUNT={c} disagrees with --shards {s}: drop --shards or \
                     size the array to match"
                ));
            }
            (Some(c), _) => index_u32(c, "SLURM_ARRAY_TASK_COUNT")?,
            (None, Some(s)) => s,
            (None, None) => {
                return Err(
                    "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not: \
                            pass --shards N"
                        .into(),
                );
            }
        };
        if id < min || (id - min) % step != 0 {
            return Err(format!(
                "SLURM_ARRAY_TASK_ID={id} is not in the array starting at \
                 SLURM_ARRAY_TASK_MIN={min} with step {step}"
            ));
        }
        let index = index_u32((id - min) / step, "Slurm array index")?;
        return Ok((Shard::new(index, count)?, ShardSource::Slurm));
    }
    if let Some(i) = number("JOB_COMPLETION_INDEX")? {
        let count = count_of("JOB_COMPLETION_INDEX")?;
        let index = index_u32(i, "JOB_COMPLETION_INDEX")?;
        return Ok((Shard::new(index, count)?, ShardSource::Kubernetes));
    }
    if let Some(seq) = number("PARALLEL_SEQ")? {
        let count = count_of("PARALLEL_SEQ")?;
        if seq == 0 {
            return Err("PARALLEL_SEQ=0: GNU parallel numbers its jobs from 1".into());
        }
        let index = index_u32(seq - 1, "PARALLEL_SEQ")?;
        return Ok((Shard::new(index, count)?, ShardSource::GnuParallel));
    }
    Err(
        "--shard auto found no scheduler: none of SLURM_ARRAY_TASK_ID (Slurm job array), \
         JOB_COMPLETION_INDEX (Kubernetes Indexed Job) or PARALLEL_SEQ (GNU parallel) is set"
            .into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> + use<> {
        let map: HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| map.get(k).cloned()
    }

    #[test]
    fn shards_are_contiguous_balanced_and_cover_every_frame() {
        for frames in [0, 1, 7, 12, 1000] {
            for count in 1..=9 {
                let mut next = 0;
                for index in 0..count {
                    let r = Shard::new(index, count).unwrap().frames(frames);
                    assert_eq!(r.start, next);
                    assert!(r.len() <= frames.div_ceil(count as usize));
                    assert!(r.len() >= frames / count as usize);
                    next = r.end;
                }
                assert_eq!(next, frames);
            }
        }
        assert_eq!(Shard::new(1, 3).unwrap().frames(12), 4..8);
        assert_eq!(Shard::new(2, 3).unwrap().frames(10), 6..10);
    }

    #[test]
    fn shard_options_parse_with_their_ranges_checked() {
        assert_eq!(
            "2/4".parse(),
            Ok(ShardChoice::Given(Shard { index: 2, count: 4 }))
        );
        assert_eq!("AUTO".parse(), Ok(ShardChoice::Auto));
        for bad in ["4/4", "1/0", "x/2", "3", "-1/2"] {
            assert!(bad.parse::<ShardChoice>().is_err(), "{bad}");
        }
    }

    /// Each scheduler's variables for task `i` (0-based) of 3 give shard `i` of 3.
    #[test]
    fn every_scheduler_picks_the_same_ranges() {
        for i in 0..3u32 {
            let want = Shard::new(i, 3).unwrap();
            // Slurm: `--array=1-3` numbers tasks from SLURM_ARRAY_TASK_MIN = 1.
            let id = (i + 1).to_string();
            let k8s_index = i.to_string();
            let seq = (i + 1).to_string();
            let slurm = env(&[
                ("SLURM_ARRAY_TASK_ID", &id),
                ("SLURM_ARRAY_TASK_MIN", "1"),
                ("SLURM_ARRAY_TASK_MAX", "3"),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
            ]);
            assert_eq!(
                from_environment(&slurm, None),
                Ok((want, ShardSource::Slurm))
            );
            let k8s = env(&[("JOB_COMPLETION_INDEX", &k8s_index)]);
            assert_eq!(
                from_environment(&k8s, Some(3)),
                Ok((want, ShardSource::Kubernetes))
            );
            let parallel = env(&[("PARALLEL_SEQ", &seq)]);
            assert_eq!(
                from_environment(&parallel, Some(3)),
                Ok((want, ShardSource::GnuParallel))
            );
            assert_eq!(want.frames(12), [0..4, 4..8, 8..12][i as usize]);
        }
        // A stepped array: --array=0-8:4 runs ids 0, 4, 8.
        let stepped = env(&[
            ("SLURM_ARRAY_TASK_ID", "8"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_STEP", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ]);
        assert_eq!(
            from_environment(&stepped, None).unwrap().0,
            Shard::new(2, 3).unwrap()
        );
    }

    #[test]
    fn missing_or_contradictory_variables_are_explained() {
        let e = from_environment(env(&[]), Some(3)).unwrap_err();
        assert!(e.contains("found no scheduler"), "{e}");
        let e = from_environment(env(&[("JOB_COMPLETION_INDEX", "1")]), None).unwrap_err();
        assert!(e.contains("--shards N"), "{e}");
        let e = from_environment(env(&[("PARALLEL_SEQ", "5")]), Some(4)).unwrap_err();
        assert!(e.contains("out of range"), "{e}");
        let e = from_environment(
            env(&[
                ("SLURM_ARRAY_TASK_ID", "0"),
                ("SLURM_ARRAY_TASK_COUNT", "4"),
            ]),
            Some(3),
        )
        .unwrap_err();
        assert!(e.contains("disagrees"), "{e}");
        let e = from_environment(env(&[("PARALLEL_SEQ", "two")]), Some(2)).unwrap_err();
        assert!(e.contains("PARALLEL_SEQ=`two`"), "{e}");
    }
}
