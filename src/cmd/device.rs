//! `taxel device serve|ls|rm`, and the device address shared with `taxel load`:
//! `tcp://HOST:PORT` for a device (or the simulator) on the network, anything
//! else for a mounted device folder (USB storage, SD card).

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::thread;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use serde::Deserialize;
use taxel_runtime::device::{
    Client, ClientError, DeviceInfo, Entry, ErrorCode, Refusal, Server, ServerConfig, Store, StoreConfig,
};

use crate::error::{CliError, CmdResult};
use crate::io::stdout::outln;

/// The marker file that tells `taxel load` what a mounted device folder accepts.
pub const MARKER: &str = ".taxel-device.toml";

/// How long a client waits for the device at each step.
const CLIENT_TIMEOUT: Duration = Duration::from_secs(30);
/// How often a busy device is asked again, and the first pause between asks (doubling).
const RETRIES: u32 = 5;
const FIRST_PAUSE: Duration = Duration::from_millis(200);
/// Staging files in a mounted folder older than this were left by a crashed
/// load; younger ones may belong to a load running in another process.
const STALE_STAGING: Duration = Duration::from_secs(600);

/// The marker file's keys; both optional.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Marker {
    /// The only profile the device accepts.
    profile: Option<String>,
    /// Bytes of storage set aside for bundles.
    capacity: Option<u64>,
}

/// A device to load onto.
pub enum Device {
    /// A device on the network.
    Tcp {
        /// `HOST:PORT`.
        addr: String,
        /// The open session.
        client: Client,
    },
    /// A mounted device folder.
    Folder(Store),
}

impl Device {
    /// Opens `spec`: `tcp://HOST:PORT` or a folder.
    pub fn open(spec: &str) -> Result<Device> {
        if let Some(addr) = spec.strip_prefix("tcp://") {
            let client = with_retries(|| Client::connect(addr, CLIENT_TIMEOUT))
                .with_context(|| format!("device tcp://{addr}"))?;
            return Ok(Device::Tcp { addr: addr.to_string(), client });
        }
        if let Some((scheme, _)) = spec.split_once("://") {
            bail!("device {spec}: unknown scheme {scheme:?} (expected tcp://HOST:PORT or a folder)");
        }
        let dir = PathBuf::from(spec);
        if !dir.is_dir() {
            bail!("device folder {} does not exist or is not a folder (is the device mounted?)", dir.display());
        }
        let marker = read_marker(&dir)?;
        let config =
            StoreConfig { profile: marker.profile, capacity: marker.capacity, stale_staging: Some(STALE_STAGING) };
        Ok(Device::Folder(Store::open(dir, config).map_err(anyhow::Error::new)?))
    }

    /// What the device says about itself.
    pub fn info(&self) -> Result<DeviceInfo> {
        match self {
            Device::Tcp { client, .. } => Ok(client.info().clone()),
            Device::Folder(store) => Ok(store.info()?),
        }
    }

    /// Loads `bytes` as `name`, asking again (a bounded number of times) while the device is busy.
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<Entry, ClientError> {
        match self {
            Device::Tcp { client, .. } => with_retries(|| client.load(name, bytes)),
            Device::Folder(store) => store.put(name, bytes).map_err(ClientError::Refused),
        }
    }

    /// The stored bundles.
    pub fn list(&mut self) -> Result<Vec<Entry>, ClientError> {
        match self {
            Device::Tcp { client, .. } => client.list(),
            Device::Folder(store) => store.list().map_err(ClientError::Refused),
        }
    }

    /// Deletes a stored bundle.
    pub fn delete(&mut self, name: &str) -> Result<(), ClientError> {
        match self {
            Device::Tcp { client, .. } => with_retries(|| client.delete(name)),
            Device::Folder(store) => store.delete(name).map_err(ClientError::Refused),
        }
    }

    /// Ends the session.
    pub fn close(self) {
        if let Device::Tcp { client, .. } = self {
            client.bye();
        }
    }

    /// How to name the device in messages.
    pub fn describe(&self) -> String {
        match self {
            Device::Tcp { addr, .. } => format!("tcp://{addr}"),
            Device::Folder(store) => store.dir().display().to_string(),
        }
    }
}

fn read_marker(dir: &Path) -> Result<Marker> {
    let path = dir.join(MARKER);
    if !path.exists() {
        // No marker: a plain folder that accepts any profile, limited only by its disk.
        return Ok(Marker { profile: None, capacity: None });
    }
    let text = crate::io::read_input_text(&path)?;
    toml::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "{}: {} (expected optional keys `profile = \"NAME\"` and `capacity = BYTES`)",
            path.display(),
            e.message()
        )
    })
}

/// Runs `f` again after a pause while the device says it is busy.
fn with_retries<T>(mut f: impl FnMut() -> Result<T, ClientError>) -> Result<T, ClientError> {
    let mut pause = FIRST_PAUSE;
    let mut attempt = 1;
    loop {
        match f() {
            Err(e) if e.code() == Some(ErrorCode::Busy) && attempt < RETRIES => {
                thread::sleep(pause);
                pause *= 2;
                attempt += 1;
            }
            other => return other,
        }
    }
}

/// `taxel device serve`.
pub fn serve(store: &Path, listen: &str, capacity: Option<u64>, profile: Option<&str>) -> CmdResult {
    let addr: SocketAddr =
        listen.parse().with_context(|| format!("--listen {listen}: expected an address such as 127.0.0.1:7878"))?;
    if !addr.ip().is_loopback() {
        // The simulator has no authentication: anyone who can reach it can
        // replace or delete bundles.
        return Err(
            anyhow::anyhow!("--listen {listen}: the simulator listens on loopback only (127.0.0.1 or [::1])").into()
        );
    }
    // The device keeps the profile's name.
    let profile = profile.map(|p| crate::io::load::profile(p).map(|p| p.name.as_str().to_string())).transpose()?;
    let config = StoreConfig { profile: profile.clone(), capacity, stale_staging: None };
    let store = Store::open(store, config).map_err(anyhow::Error::new)?;
    let server =
        Server::bind(addr, store, ServerConfig::default()).with_context(|| format!("cannot listen on {addr}"))?;
    let bound = server.local_addr()?;
    outln!(
        "taxel device simulator listening on tcp://{bound} (store {}, profile {}, capacity {})",
        server.store().dir().display(),
        profile.as_deref().unwrap_or("any"),
        capacity.map_or_else(|| "unlimited".to_string(), |c| format!("{c} bytes")),
    )?;
    server.run();
    Ok(())
}

/// `taxel device ls`.
pub fn ls(spec: &str) -> CmdResult {
    let mut device = Device::open(spec)?;
    let info = device.info()?;
    let entries = device.list().with_context(|| format!("device {}", device.describe()))?;
    let profile = if info.profile.is_empty() { "any" } else { info.profile.as_str() };
    let free = if info.free == u64::MAX { "unlimited".to_string() } else { format!("{} bytes", info.free) };
    outln!("{}: profile {profile}, {} bundles, free {free}", device.describe(), entries.len())?;
    for e in &entries {
        let sum: String = e.checksum[..8].iter().map(|b| format!("{b:02x}")).collect();
        outln!("{:<40} {:>12} {sum}", e.name, e.size)?;
    }
    device.close();
    Ok(())
}

/// `taxel device rm`.
pub fn rm(name: &str, spec: &str) -> CmdResult {
    let mut device = Device::open(spec)?;
    let result = device.delete(name);
    let described = device.describe();
    device.close();
    match result {
        Ok(()) => outln!("deleted {name} from {described}"),
        Err(ClientError::Refused(Refusal { code: ErrorCode::NotFound | ErrorCode::InvalidName, message })) => {
            Err(CliError::input(anyhow::anyhow!("{described}: {message}")))
        }
        Err(e) => Err(CliError::trouble(anyhow::Error::new(e).context(format!("device {described}")))),
    }
}
