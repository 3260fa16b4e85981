//! A device's bundle store: one folder, one file per bundle, and the rules
//! that keep it consistent whatever happens to a transfer.
//!
//! A new bundle is written to a staging file (`.taxel-staging-*`) in the same
//! folder. Only when every byte has arrived, the checksum matches, the bundle
//! validates and its profile is the device's, is the staging file flushed to
//! disk and renamed over the old bundle of the same name, and the folder
//! flushed. Until then the old bundle is untouched; a transfer that ends
//! early deletes its staging file, and a store that is opened again deletes
//! staging files left by a crash. The same rules serve the device simulator
//! and a mounted device folder (USB storage, SD card).

use std::collections::HashMap;
use std::fs::{self, File};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::string::{String, ToString};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, SystemTime};
use std::vec::Vec;
use std::{fmt, format};

use taxel_format::BundleView;

use super::protocol::{Checksum, DeviceInfo, Entry, ErrorCode, Offer, PROTOCOL_VERSION, checksum, valid_name};

/// Prefix of staging files; never a valid bundle name (names cannot start with `.`).
pub const STAGING_PREFIX: &str = ".taxel-staging-";

/// A refusal or failure of the store, with the protocol's error code.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The protocol's code for it.
    pub code: ErrorCode,
    /// Details for people.
    pub message: String,
}

impl Refusal {
    /// A refusal with `code` and `message`.
    pub fn new(code: ErrorCode, message: impl Into<String>) -> Self {
        Refusal { code, message: message.into() }
    }

    fn storage(what: &str, path: &Path, e: std::io::Error) -> Self {
        Refusal::new(ErrorCode::Storage, format!("{what} {}: {e}", path.display()))
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.code, self.message)
    }
}

impl std::error::Error for Refusal {}

/// How a store is set up.
#[derive(Debug, Clone, Default)]
pub struct StoreConfig {
    /// The only profile whose bundles the device accepts; `None` accepts any.
    pub profile: Option<String>,
    /// Storage capacity in bytes; `None` for no limit beyond the disk's own.
    pub capacity: Option<u64>,
    /// Staging files older than this are removed on open; `None` removes all
    /// of them (right for a store that one process owns, such as the simulator).
    pub stale_staging: Option<Duration>,
}

/// A folder of bundles kept like a device keeps them.
#[derive(Debug)]
pub struct Store {
    dir: PathBuf,
    config: StoreConfig,
    /// Names being loaded and the bytes reserved for each. One lock for the
    /// whole store: it guards only bookkeeping and renames, never a transfer.
    reserved: Mutex<HashMap<String, u64>>,
}

impl Store {
    /// Opens (creating if needed) the store in `dir` and removes staging files
    /// left by interrupted transfers.
    pub fn open(dir: impl Into<PathBuf>, config: StoreConfig) -> Result<Store, Refusal> {
        let dir = dir.into();
        fs::create_dir_all(&dir).map_err(|e| Refusal::storage("cannot create", &dir, e))?;
        let entries = fs::read_dir(&dir).map_err(|e| Refusal::storage("cannot read", &dir, e))?;
        let now = SystemTime::now();
        for entry in entries.flatten() {
            if !entry.file_name().to_string_lossy().starts_with(STAGING_PREFIX) {
                continue;
            }
            let stale = match config.stale_staging {
                None => true,
                Some(age) => entry
                    .metadata()
                    .and_then(|m| m.modified())
                    .map(|t| now.duration_since(t).unwrap_or_default() >= age)
                    .unwrap_or(true),
            };
            if stale {
                // A file that cannot be removed now is retried on the next open.
                let _ = fs::remove_file(entry.path());
            }
        }
        Ok(Store { dir, config, reserved: Mutex::new(HashMap::new()) })
    }

    /// The store's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The profile the device accepts, if it checks one.
    pub fn profile(&self) -> Option<&str> {
        self.config.profile.as_deref()
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<String, u64>> {
        // A poisoned lock only means a thread panicked while holding it; the
        // map is still a valid record of reservations.
        self.reserved.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Bytes taken by stored bundles.
    fn used(&self) -> Result<u64, Refusal> {
        Ok(self.stored_files()?.iter().map(|(_, size)| size).sum())
    }

    fn stored_files(&self) -> Result<Vec<(String, u64)>, Refusal> {
        let entries = fs::read_dir(&self.dir).map_err(|e| Refusal::storage("cannot read", &self.dir, e))?;
        let mut out = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| Refusal::storage("cannot read", &self.dir, e))?;
            let Ok(name) = entry.file_name().into_string() else { continue };
            if !valid_name(&name) {
                continue;
            }
            match entry.metadata() {
                Ok(m) if m.is_file() => out.push((name, m.len())),
                _ => {}
            }
        }
        out.sort();
        Ok(out)
    }

    fn free_locked(&self, reserved: &HashMap<String, u64>) -> Result<u64, Refusal> {
        let Some(capacity) = self.config.capacity else { return Ok(u64::MAX) };
        let taken = self.used()?.saturating_add(reserved.values().sum());
        Ok(capacity.saturating_sub(taken))
    }

    /// Free bytes now (`u64::MAX` when unlimited).
    pub fn free(&self) -> Result<u64, Refusal> {
        let reserved = self.lock();
        self.free_locked(&reserved)
    }

    /// What the device says about itself.
    pub fn info(&self) -> Result<DeviceInfo, Refusal> {
        Ok(DeviceInfo {
            version: PROTOCOL_VERSION,
            profile: self.config.profile.clone().unwrap_or_default(),
            capacity: self.config.capacity.unwrap_or(u64::MAX),
            free: self.free()?,
        })
    }

    /// The stored bundles, sorted by name, each with the checksum of its bytes.
    pub fn list(&self) -> Result<Vec<Entry>, Refusal> {
        let mut out = Vec::new();
        for (name, _) in self.stored_files()? {
            let path = self.dir.join(&name);
            // A bundle deleted between listing and reading is simply not listed.
            let Ok(bytes) = fs::read(&path) else { continue };
            out.push(Entry { name, size: bytes.len() as u64, checksum: checksum(&bytes) });
        }
        Ok(out)
    }

    /// Reads a stored bundle.
    pub fn read(&self, name: &str) -> Result<Vec<u8>, Refusal> {
        check_name(name)?;
        let path = self.dir.join(name);
        fs::read(&path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => Refusal::new(ErrorCode::NotFound, format!("no bundle named {name}")),
            _ => Refusal::storage("cannot read", &path, e),
        })
    }

    /// Accepts an offer: checks the name, the profile and the free space,
    /// reserves the space and the name, and opens a staging file.
    pub fn begin(&self, offer: &Offer) -> Result<Upload<'_>, Refusal> {
        check_name(&offer.name)?;
        self.check_profile(&offer.profile)?;
        if offer.size > taxel_format::MAX_FILE_LEN {
            return Err(Refusal::new(
                ErrorCode::InvalidBundle,
                format!("{} bytes is larger than any bundle may be ({})", offer.size, taxel_format::MAX_FILE_LEN),
            ));
        }
        let mut reserved = self.lock();
        if reserved.contains_key(&offer.name) {
            return Err(Refusal::new(ErrorCode::Busy, format!("{} is being loaded by another client", offer.name)));
        }
        let free = self.free_locked(&reserved)?;
        if offer.size > free {
            return Err(Refusal::new(
                ErrorCode::NoSpace,
                format!("{} needs {} bytes but only {free} are free", offer.name, offer.size),
            ));
        }
        let file = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempfile_in(&self.dir)
            .map_err(|e| Refusal::storage("cannot create a staging file in", &self.dir, e))?;
        reserved.insert(offer.name.clone(), offer.size);
        Ok(Upload {
            store: self,
            name: offer.name.clone(),
            size: offer.size,
            checksum: offer.checksum,
            file: Some(file),
            written: 0,
        })
    }

    /// Stores `bytes` as `name` in one call (the path of a mounted device folder).
    pub fn put(&self, name: &str, bytes: &[u8]) -> Result<Entry, Refusal> {
        let profile = taxel_format::stored::plain(bytes)
            .and_then(|p| BundleView::parse(&p).map(|v| v.manifest().profile.name.as_str().to_string()))
            .map_err(|e| Refusal::new(ErrorCode::InvalidBundle, format!("{name}: {e}")))?;
        let offer = Offer { name: name.into(), profile, size: bytes.len() as u64, checksum: checksum(bytes) };
        let mut upload = self.begin(&offer)?;
        upload.write(bytes)?;
        upload.commit()
    }

    /// Deletes a stored bundle (refused while it is being loaded).
    pub fn delete(&self, name: &str) -> Result<(), Refusal> {
        check_name(name)?;
        let reserved = self.lock();
        if reserved.contains_key(name) {
            return Err(Refusal::new(ErrorCode::Busy, format!("{name} is being loaded by another client")));
        }
        let path = self.dir.join(name);
        match fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(Refusal::new(ErrorCode::NotFound, format!("no bundle named {name}")));
            }
            Err(e) => return Err(Refusal::storage("cannot delete", &path, e)),
        }
        sync_dir(&self.dir).map_err(|e| Refusal::storage("cannot flush", &self.dir, e))
    }

    fn check_profile(&self, profile: &str) -> Result<(), Refusal> {
        match &self.config.profile {
            Some(p) if p != profile => Err(Refusal::new(
                ErrorCode::WrongProfile,
                format!("the bundle is for profile {profile:?} but this device is {p:?}"),
            )),
            _ => Ok(()),
        }
    }
}

fn check_name(name: &str) -> Result<(), Refusal> {
    if valid_name(name) {
        Ok(())
    } else {
        Err(Refusal::new(
            ErrorCode::InvalidName,
            format!("{name:?} is not a plain bundle name (1-64 letters, digits, '-', '_', '.', not starting with '.')"),
        ))
    }
}

/// Flushes a folder's entries (the rename) to disk. Windows has no such call;
/// there a rename is flushed with the file system's own journal.
fn sync_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        File::open(dir)?.sync_all()
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

/// One bundle being received. Dropping it without [`Upload::commit`] deletes
/// the staging file and releases the name and the space.
#[derive(Debug)]
pub struct Upload<'a> {
    store: &'a Store,
    name: String,
    size: u64,
    checksum: Checksum,
    file: Option<tempfile::NamedTempFile>,
    written: u64,
}

impl Upload<'_> {
    /// The bundle's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Appends received bytes; more bytes than offered is a refusal.
    pub fn write(&mut self, data: &[u8]) -> Result<(), Refusal> {
        let Some(file) = self.file.as_mut() else {
            return Err(Refusal::new(ErrorCode::Protocol, "the upload is already finished"));
        };
        if self.written + data.len() as u64 > self.size {
            return Err(Refusal::new(
                ErrorCode::SizeMismatch,
                format!("{}: more than the offered {} bytes arrived", self.name, self.size),
            ));
        }
        file.write_all(data).map_err(|e| Refusal::storage("cannot write", file.path(), e))?;
        self.written += data.len() as u64;
        Ok(())
    }

    /// Verifies the received bundle and puts it in place of any older one of
    /// the same name.
    pub fn commit(mut self) -> Result<Entry, Refusal> {
        let Some(mut file) = self.file.take() else {
            return Err(Refusal::new(ErrorCode::Protocol, "the upload is already finished"));
        };
        if self.written != self.size {
            return Err(Refusal::new(
                ErrorCode::SizeMismatch,
                format!("{}: {} of the offered {} bytes arrived", self.name, self.written, self.size),
            ));
        }
        file.as_file().sync_all().map_err(|e| Refusal::storage("cannot flush", file.path(), e))?;
        // Verify what is on the storage, not what was meant to be written.
        let mut bytes = Vec::with_capacity(self.size as usize);
        let read_back = {
            let f = file.as_file_mut();
            f.rewind().and_then(|()| f.read_to_end(&mut bytes))
        };
        read_back.map_err(|e| Refusal::storage("cannot read back", file.path(), e))?;
        if checksum(&bytes) != self.checksum {
            return Err(Refusal::new(
                ErrorCode::ChecksumMismatch,
                format!("{}: the received bytes do not match the offered checksum", self.name),
            ));
        }
        let invalid = |e| Refusal::new(ErrorCode::InvalidBundle, format!("{}: {e}", self.name));
        let plain = taxel_format::stored::plain(&bytes).map_err(invalid)?;
        let view = BundleView::parse(&plain).map_err(invalid)?;
        self.store.check_profile(view.manifest().profile.name.as_str())?;
        let target = self.store.dir.join(&self.name);
        {
            // Rename under the lock so that space accounting never sees the
            // old and new bundle both counted as stored and reserved at once.
            let mut reserved = self.store.lock();
            file.persist(&target).map_err(|e| Refusal::storage("cannot rename into", &target, e.error))?;
            reserved.remove(&self.name);
        }
        sync_dir(&self.store.dir).map_err(|e| Refusal::storage("cannot flush", &self.store.dir, e))?;
        Ok(Entry { name: self.name.clone(), size: self.size, checksum: self.checksum })
    }
}

impl Drop for Upload<'_> {
    fn drop(&mut self) {
        // The staging file (if still there) is deleted by its own drop.
        self.file = None;
        self.store.lock().remove(&self.name);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::{Bundle, Manifest, profiles};

    fn bundle(profile: &str) -> Vec<u8> {
        Bundle::new(Manifest::new(profiles::builtin(profile).unwrap())).to_bytes().unwrap()
    }

    fn store(dir: &Path, profile: Option<&str>, capacity: Option<u64>) -> Store {
        Store::open(dir, StoreConfig { profile: profile.map(Into::into), capacity, stale_staging: None }).unwrap()
    }

    fn staging_files(dir: &Path) -> usize {
        fs::read_dir(dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with(STAGING_PREFIX))
            .count()
    }

    #[test]
    fn put_then_list_then_delete() {
        let dir = tempfile::tempdir().unwrap();
        let s = store(dir.path(), Some("stress2"), None);
        let b = bundle("stress2");
        let e = s.put("a.taxel", &b).unwrap();
        assert_eq!(e.checksum, *blake3::hash(&b).as_bytes());
        assert_eq!(s.list().unwrap(), std::vec![e]);
        s.delete("a.taxel").unwrap();
        assert!(s.list().unwrap().is_empty());
        assert_eq!(s.delete("a.taxel").unwrap_err().code, ErrorCode::NotFound);
    }

    #[test]
    fn an_abandoned_upload_leaves_no_staging_file_and_frees_its_space() {
        let dir = tempfile::tempdir().unwrap();
        let b = bundle("stress2");
        let s = store(dir.path(), None, Some(b.len() as u64));
        let offer = Offer { name: "a".into(), profile: "stress2".into(), size: b.len() as u64, checksum: checksum(&b) };
        {
            let mut u = s.begin(&offer).unwrap();
            u.write(&b[..10]).unwrap();
            assert_eq!(staging_files(dir.path()), 1);
            assert_eq!(s.free().unwrap(), 0);
            assert_eq!(s.begin(&offer).unwrap_err().code, ErrorCode::Busy);
        }
        assert_eq!(staging_files(dir.path()), 0);
        assert_eq!(s.free().unwrap(), b.len() as u64);
    }

    #[test]
    fn reopening_removes_staging_files_left_by_a_crash() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(format!("{STAGING_PREFIX}x")), b"half").unwrap();
        let s = store(dir.path(), None, None);
        assert_eq!(staging_files(dir.path()), 0);
        assert!(s.list().unwrap().is_empty());
    }

    #[test]
    fn a_fresh_staging_file_of_another_process_survives_a_stale_only_cleanup() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(format!("{STAGING_PREFIX}x")), b"half").unwrap();
        let config = StoreConfig { stale_staging: Some(Duration::from_secs(600)), ..Default::default() };
        Store::open(dir.path(), config).unwrap();
        assert_eq!(staging_files(dir.path()), 1);
    }
}
