//! The on-disk pipeline cache: the driver's compiled pipelines, saved after the first run on
//! an adapter so that later processes skip most shader compilation.
//!
//! One file per adapter under the user's cache folder ([`cache_dir`]). Its header names the
//! adapter key, the wgpu version and a hash of every shader source, and an MD5 covers the
//! payload, so a file from another adapter, another build or a broken write is ignored (with
//! a reason) and rewritten, never handed to the driver.

use std::io::Write;
use std::path::{Path, PathBuf};

use md5::{Digest, Md5};

/// Environment variable naming the cache folder; `off` turns the cache off.
pub const CACHE_DIR_ENV: &str = "OMNICLOUD_CACHE_DIR";

/// First bytes of every cache file.
const MAGIC: &[u8; 8] = b"OCPLC\x00\x00\x01";

/// What happened to the cache when the rasterizer started.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CacheStatus {
    /// No cache: turned off, no cache folder, or a backend without pipeline caches.
    Off(String),
    /// No file yet (or a stale one): pipelines compiled from scratch, file written.
    Created(PathBuf),
    /// A valid file was loaded and handed to the driver.
    Loaded(PathBuf),
    /// A file existed but was unusable; it was ignored and rewritten.
    Ignored {
        /// The file.
        path: PathBuf,
        /// Why it was not used.
        reason: String,
    },
}

impl std::fmt::Display for CacheStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CacheStatus::Off(why) => write!(f, "pipeline cache off ({why})"),
            CacheStatus::Created(p) => write!(f, "pipeline cache created: {}", p.display()),
            CacheStatus::Loaded(p) => write!(f, "pipeline cache loaded: {}", p.display()),
            CacheStatus::Ignored { path, reason } => write!(
                f,
                "ignored the pipeline cache {} ({reason}); rebuilt it",
                path.display()
            ),
        }
    }
}

/// The folder the cache goes in: `$OMNICLOUD_CACHE_DIR`, else the platform's user cache
/// folder (`$XDG_CACHE_HOME` or `~/.cache` on Linux) + `omnicloud`. `Err` says why there
/// is none.
pub fn cache_dir() -> Result<PathBuf, String> {
    match std::env::var_os(CACHE_DIR_ENV) {
        Some(v) if v == "off" => Err(format!("{CACHE_DIR_ENV}=off")),
        Some(v) if !v.is_empty() => Ok(PathBuf::from(v)),
        _ => dirs::cache_dir()
            .map(|d| d.join("omnicloud"))
            .ok_or_else(|| "no user cache folder".to_string()),
    }
}

/// A cache file's identity: which adapter and which shaders its pipelines belong to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CacheKey {
    /// wgpu's adapter key (vendor and device), also the file name.
    adapter: String,
    /// Adapter driver, wgpu version and shader hash: what must match for the data to apply.
    build: String,
}

impl CacheKey {
    /// The key for `info` and the shader `sources`; `None` when the backend keeps no
    /// pipeline cache (wgpu supports them on Vulkan).
    pub fn new(info: &wgpu::AdapterInfo, sources: &[&str]) -> Option<CacheKey> {
        let adapter = wgpu::util::pipeline_cache_key(info)?;
        let mut hash = Md5::new();
        for s in sources {
            hash.update((s.len() as u64).to_le_bytes());
            hash.update(s.as_bytes());
        }
        let shaders: String = hash.finalize().iter().map(|b| format!("{b:02x}")).collect();
        // wgpu's own header and the driver's cache UUID reject data from other versions;
        // the shader hash keeps a rebuilt binary from loading pipelines of old shaders.
        let build = format!(
            "{} {} | {} | shaders {shaders}",
            info.driver, info.driver_info, info.name
        );
        Some(CacheKey { adapter, build })
    }

    /// The cache file for this adapter in `dir`.
    pub fn file_in(&self, dir: &Path) -> PathBuf {
        dir.join(format!("{}.bin", self.adapter))
    }
}

/// Reads a cache file written by [`encode`] for `key`: the driver payload, or why the file
/// is unusable.
pub fn decode<'a>(bytes: &'a [u8], key: &CacheKey) -> Result<&'a [u8], String> {
    let rest = bytes
        .strip_prefix(MAGIC)
        .ok_or("not an omnicloud pipeline cache")?;
    let (len, rest) = take_u32(rest).ok_or("truncated header")?;
    let build = rest.get(..len as usize).ok_or("truncated header")?;
    let rest = &rest[len as usize..];
    if build != key.build.as_bytes() {
        return Err("made by another driver, build or shader version".into());
    }
    let (digest, rest) = rest.split_at_checked(16).ok_or("truncated header")?;
    let (len, payload) = take_u64(rest).ok_or("truncated header")?;
    if payload.len() as u64 != len {
        return Err(format!(
            "truncated: {} of {len} payload bytes",
            payload.len()
        ));
    }
    if Md5::digest(payload).as_slice() != digest {
        return Err("checksum mismatch".into());
    }
    Ok(payload)
}

/// The file bytes holding `payload` for `key`.
pub fn encode(payload: &[u8], key: &CacheKey) -> Vec<u8> {
    let mut out = Vec::with_capacity(payload.len() + key.build.len() + 40);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&(key.build.len() as u32).to_le_bytes());
    out.extend_from_slice(key.build.as_bytes());
    out.extend_from_slice(&Md5::digest(payload));
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

fn take_u32(b: &[u8]) -> Option<(u32, &[u8])> {
    let (head, rest) = b.split_at_checked(4)?;
    Some((u32::from_le_bytes(head.try_into().ok()?), rest))
}

fn take_u64(b: &[u8]) -> Option<(u64, &[u8])> {
    let (head, rest) = b.split_at_checked(8)?;
    Some((u64::from_le_bytes(head.try_into().ok()?), rest))
}

/// A device's pipeline cache while the rasterizer compiles, and where it is saved.
pub struct PipelineCache {
    /// Handed to every pipeline descriptor; `None` when off.
    pub cache: Option<wgpu::PipelineCache>,
    key: Option<(CacheKey, PathBuf)>,
    status: CacheStatus,
    /// MD5 of the payload the file holds now (loaded or last written).
    on_disk: Option<[u8; 16]>,
}

impl PipelineCache {
    /// Opens the cache for `device` on an adapter described by `info`; `enabled` is false when
    /// the device lacks `PIPELINE_CACHE`.
    pub fn open(
        device: &wgpu::Device,
        info: &wgpu::AdapterInfo,
        enabled: bool,
        sources: &[&str],
    ) -> PipelineCache {
        let off = |why: &str| PipelineCache {
            cache: None,
            key: None,
            status: CacheStatus::Off(why.to_string()),
            on_disk: None,
        };
        if !enabled {
            return off("the device has no pipeline cache");
        }
        let Some(key) = CacheKey::new(info, sources) else {
            return off("the backend keeps no pipeline cache");
        };
        let dir = match cache_dir() {
            Ok(d) => d,
            Err(why) => return off(&why),
        };
        let path = key.file_in(&dir);
        let (data, status) = match std::fs::read(&path) {
            Ok(bytes) => match decode(&bytes, &key) {
                Ok(payload) => (Some(payload.to_vec()), CacheStatus::Loaded(path.clone())),
                Err(reason) => (
                    None,
                    CacheStatus::Ignored {
                        path: path.clone(),
                        reason,
                    },
                ),
            },
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                (None, CacheStatus::Created(path.clone()))
            }
            Err(e) => (
                None,
                CacheStatus::Ignored {
                    path: path.clone(),
                    reason: e.to_string(),
                },
            ),
        };
        // SAFETY: `data` is what `get_data` returned for an adapter with the same wgpu cache
        // key (the file's header and checksum are checked above), as the call requires.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("omnicloud pipelines"),
                data: data.as_deref(),
                fallback: true,
            })
        };
        PipelineCache {
            cache: Some(cache),
            key: Some((key, path)),
            status,
            on_disk: data.as_deref().map(|d| Md5::digest(d).into()),
        }
    }

    /// What happened when it was opened.
    pub fn status(&self) -> &CacheStatus {
        &self.status
    }

    /// Writes the cache back after compiling, unless the file already holds what the driver
    /// has. A failure to write only turns the status into a reason: the cache is an
    /// optimisation.
    pub fn save(&mut self) {
        let (Some(cache), Some((key, path))) = (&self.cache, &self.key) else {
            return;
        };
        let Some(payload) = cache.get_data() else {
            return;
        };
        let digest: [u8; 16] = Md5::digest(&payload).into();
        if self.on_disk == Some(digest) {
            return;
        }
        let bytes = encode(&payload, key);
        let written = path
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(|e| e.to_string())
            .and_then(|()| {
                crate::output::atomic::write_atomically(path, |w| {
                    w.write_all(&bytes)
                        .map_err(|source| crate::output::OutputError::Io {
                            path: path.clone(),
                            action: "writing",
                            source,
                        })
                })
                .map_err(|e| e.to_string())
            });
        match written {
            Ok(()) => self.on_disk = Some(digest),
            Err(reason) => {
                let why = format!("could not write {}: {reason}", path.display());
                self.status = CacheStatus::Off(why);
                self.key = None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> CacheKey {
        CacheKey {
            adapter: "wgpu_pipeline_cache_vulkan_1_2".into(),
            build: "driver | adapter | wgpu 30 | shaders abc".into(),
        }
    }

    #[test]
    fn a_file_round_trips() {
        let bytes = encode(b"driver data", &key());
        assert_eq!(decode(&bytes, &key()).unwrap(), b"driver data");
    }

    #[test]
    fn garbage_truncation_corruption_and_other_builds_are_refused() {
        let k = key();
        let good = encode(&[7u8; 100], &k);
        assert_eq!(
            decode(b"garbage garbage", &k).unwrap_err(),
            "not an omnicloud pipeline cache"
        );
        assert!(
            decode(&good[..good.len() - 1], &k)
                .unwrap_err()
                .starts_with("truncated")
        );
        assert!(
            decode(&good[..12], &k)
                .unwrap_err()
                .starts_with("truncated")
        );
        let mut flipped = good.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert_eq!(decode(&flipped, &k).unwrap_err(), "checksum mismatch");
        let other = CacheKey {
            build: "driver | adapter | wgpu 30 | shaders def".into(),
            ..k.clone()
        };
        assert!(decode(&good, &other).unwrap_err().contains("another"));
    }
}
