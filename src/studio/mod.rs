//! `taxel studio [PATH] [--port N] [--no-open] [--listen ADDR]`: a local web
//! app, served by this binary, in which a teacher opens a drawing, sees what
//! will be felt and why, and downloads the bundle, and a student explores
//! it; the page plays bundles with the runtime compiled to WebAssembly
//! (`runtime-wasm/`). See `docs/studio.md`.
//!
//! - [`routes`]: what each URL does.
//! - [`work`]: the CLI's pipeline on one file (compile, account, preview, export).
//! - [`security`]: own Host and Origin only, paths inside the opened folder.
//! - [`assets`]: the page's files, embedded.

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use anyhow::Context;

use crate::cli::CompileOpts;
use crate::error::CmdResult;

pub mod assets;
mod routes;
pub mod security;
mod work;

/// The port `taxel studio` listens on unless `--port` says otherwise.
pub const DEFAULT_PORT: u16 = 8470;
/// How many built files the studio keeps for the page to ask for their parts.
const KEPT: usize = 8;
/// Threads answering requests: a build of a large map takes a second, and
/// the page meanwhile asks for pictures.
const WORKERS: usize = 4;

/// `taxel studio`'s arguments.
#[derive(Debug, Clone)]
pub struct StudioArgs {
    /// A drawing, mesh, bundle or folder; the current folder when omitted.
    pub path: Option<PathBuf>,
    /// The port (0: any free one).
    pub port: Option<u16>,
    /// Do not open a browser.
    pub no_open: bool,
    /// The address to listen on (127.0.0.1 unless given).
    pub listen: Option<std::net::IpAddr>,
    /// The compile options every build starts from (the page may change the profile).
    pub opts: CompileOpts,
}

/// The studio's state, shared by the request threads.
pub struct Studio {
    /// The folder the studio may read and write in (canonical).
    pub root: PathBuf,
    /// The file given on the command line, relative to `root`.
    pub file: Option<String>,
    /// Hosts and origins that are the studio's own.
    pub hosts: security::Hosts,
    /// The options builds start from.
    pub opts: CompileOpts,
    /// Built files, newest last.
    kept: Mutex<Kept>,
    /// Files the page made, which builds read by path as the command line
    /// reads its own: profile files uploaded and the teacher's style sheets
    /// (see [`Studio::stash`]). Removed when the studio stops.
    scratch: tempfile::TempDir,
}

/// The last id given and the built files kept, newest last, by id.
type Kept = (u64, VecDeque<(u64, Arc<work::Built>)>);

impl Studio {
    /// A studio over `path` (a file or a folder) answering at `addr`.
    pub fn new(path: &Path, addr: SocketAddr, opts: CompileOpts) -> anyhow::Result<Self> {
        let real = path.canonicalize().with_context(|| format!("cannot open {}", path.display()))?;
        let (root, file) = if real.is_dir() {
            (real, None)
        } else {
            let root = real.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("/"));
            let name = real.file_name().map(|n| n.to_string_lossy().into_owned());
            (root, name)
        };
        let scratch = tempfile::tempdir().context("cannot make the studio's temporary folder")?;
        Ok(Studio {
            root,
            file,
            hosts: security::Hosts::new(addr),
            opts,
            kept: Mutex::new((0, VecDeque::new())),
            scratch,
        })
    }

    /// Writes `text` into the scratch folder as `KIND-HASH.toml` (its
    /// content's hash: the same text is the same file) and returns the
    /// file's key (`KIND-HASH`) and path. A build names it by path, so the
    /// bundle's content hash covers its bytes exactly as `taxel build
    /// --profile FILE` or `--style FILE` covers the teacher's own file.
    fn stash(&self, kind: &str, text: &str) -> anyhow::Result<(String, PathBuf)> {
        let hash = blake3::hash(text.as_bytes()).to_hex();
        let key = format!("{kind}-{}", &hash.as_str()[..32]);
        let path = self.scratch.path().join(format!("{key}.toml"));
        if !path.is_file() {
            crate::io::write_file(&path, text.as_bytes())?;
        }
        Ok((key, path))
    }

    /// The path of a file [`Studio::stash`] wrote under `key`, if there is one
    /// (the key is checked: a kind, a dash and hexadecimal digits only).
    fn stashed(&self, kind: &str, key: &str) -> Option<PathBuf> {
        let hash = key.strip_prefix(kind)?.strip_prefix('-')?;
        if hash.len() != 32 || !hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        Some(self.scratch.path().join(format!("{key}.toml"))).filter(|p| p.is_file())
    }

    /// Keeps `built` and returns its id; the oldest is forgotten past [`KEPT`].
    fn keep(&self, built: work::Built) -> (u64, Arc<work::Built>) {
        let mut kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
        kept.0 += 1;
        let id = kept.0;
        let built = Arc::new(built);
        kept.1.push_back((id, built.clone()));
        while kept.1.len() > KEPT {
            kept.1.pop_front();
        }
        (id, built)
    }

    /// The built file `id`, if it is still kept.
    fn kept(&self, id: u64) -> Option<Arc<work::Built>> {
        let kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
        kept.1.iter().find(|(i, _)| *i == id).map(|(_, b)| b.clone())
    }
}

/// Runs the studio until Ctrl-C.
pub fn run(args: StudioArgs) -> CmdResult {
    let path = args.path.clone().unwrap_or_else(|| PathBuf::from("."));
    let ip = args.listen.unwrap_or(std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST));
    let server = bind(ip, args.port)?;
    let addr = server.server_addr().to_ip().context("the server has no IP address")?;
    let studio = Arc::new(Studio::new(&path, addr, args.opts.clone())?);
    let host = if addr.ip().is_loopback() { format!("127.0.0.1:{}", addr.port()) } else { addr.to_string() };
    let url = format!("http://{host}/");
    println!("taxel studio: {url} (serving {}); Ctrl-C stops it", studio.root.display());
    if !ip.is_loopback() {
        eprintln!("warning: --listen {ip}: the studio is reachable from other machines on this network");
    }
    if !args.no_open && open::that_detached(&url).is_err() {
        eprintln!("note: no browser could be opened; open {url} yourself");
    }
    serve(server, studio)
}

/// Listens on `ip` and `port`: [`DEFAULT_PORT`] unless given; when the
/// default port is taken, any free one.
fn bind(ip: std::net::IpAddr, port: Option<u16>) -> anyhow::Result<tiny_http::Server> {
    let at = |p: u16| tiny_http::Server::http(SocketAddr::new(ip, p));
    match port {
        Some(p) => at(p).map_err(|e| anyhow::anyhow!("cannot listen on {ip}:{p}: {e}")),
        None => at(DEFAULT_PORT).or_else(|_| at(0)).map_err(|e| anyhow::anyhow!("cannot listen on {ip}: {e}")),
    }
}

/// Answers requests on [`WORKERS`] threads until Ctrl-C; requests in
/// progress are finished first.
fn serve(server: tiny_http::Server, studio: Arc<Studio>) -> CmdResult {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst)).context("cannot catch Ctrl-C")?;
    }
    let server = Arc::new(server);
    let workers: Vec<_> = (0..WORKERS)
        .map(|_| {
            let (server, studio, stop) = (server.clone(), studio.clone(), stop.clone());
            std::thread::Builder::new()
                .stack_size(crate::WORKER_STACK)
                .spawn(move || {
                    while !stop.load(Ordering::SeqCst) {
                        match server.recv_timeout(Duration::from_millis(200)) {
                            Ok(Some(request)) => routes::answer(&studio, request),
                            Ok(None) => {}
                            Err(e) => eprintln!("warning: studio: {e}"),
                        }
                    }
                })
                .context("cannot start the studio's threads")
        })
        .collect::<Result<_, _>>()?;
    for w in workers {
        let _ = w.join();
    }
    println!("taxel studio stopped");
    Ok(())
}
