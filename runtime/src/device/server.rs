//! The device simulator's server: accepts loader connections on TCP and
//! keeps bundles in a [`Store`] the way a device with limited storage would.
//!
//! Each connection runs on its own thread; at most
//! [`ServerConfig::max_clients`] at once, and a client beyond that is told
//! `BUSY` and disconnected. Every frame must arrive within
//! [`ServerConfig::timeout`] of the device starting to wait for it, so a
//! stalled or trickling client cannot hold the device. Stopping the server
//! (or dropping its [`ServerHandle`]) closes every connection; a transfer cut
//! that way leaves the store as it was.

use std::io::{self, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::string::String;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};
use std::vec::Vec;

use super::protocol::{ErrorCode, PROTOCOL_VERSION, ProtocolError, Reply, Request, read_frame, write_frame};
use super::store::{Refusal, Store, Upload};

/// How a server treats its clients.
#[derive(Debug, Clone, Copy)]
pub struct ServerConfig {
    /// Longest wait for one whole frame (and for a write to the client).
    pub timeout: Duration,
    /// Most clients served at once.
    pub max_clients: usize,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig { timeout: Duration::from_secs(10), max_clients: 4 }
    }
}

/// A bound, not yet running, device simulator.
#[derive(Debug)]
pub struct Server {
    listener: TcpListener,
    store: Arc<Store>,
    config: ServerConfig,
}

impl Server {
    /// Binds `addr` (use port 0 for any free port) in front of `store`.
    pub fn bind(addr: impl ToSocketAddrs, store: Store, config: ServerConfig) -> io::Result<Server> {
        Ok(Server { listener: TcpListener::bind(addr)?, store: Arc::new(store), config })
    }

    /// The address the server listens on.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// The store behind the server.
    pub fn store(&self) -> &Arc<Store> {
        &self.store
    }

    /// Serves until the process ends.
    pub fn run(self) {
        let stop = Arc::new(AtomicBool::new(false));
        accept_loop(self.listener, self.store, self.config, stop);
    }

    /// Serves on a background thread until the handle is stopped or dropped.
    pub fn spawn(self) -> io::Result<ServerHandle> {
        let addr = self.local_addr()?;
        let stop = Arc::new(AtomicBool::new(false));
        let store = self.store.clone();
        let flag = stop.clone();
        let thread = thread::Builder::new()
            .name("taxel-device".into())
            .spawn(move || accept_loop(self.listener, self.store, self.config, flag))?;
        Ok(ServerHandle { addr, stop, store, thread: Some(thread) })
    }
}

/// A running server; stopping or dropping it closes every connection and
/// waits for every connection thread to finish.
#[derive(Debug)]
pub struct ServerHandle {
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
    store: Arc<Store>,
    thread: Option<JoinHandle<()>>,
}

impl ServerHandle {
    /// The address the server listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The store behind the server.
    pub fn store(&self) -> &Arc<Store> {
        &self.store
    }

    /// Stops the server and waits until every connection is closed.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        let Some(thread) = self.thread.take() else { return };
        self.stop.store(true, Ordering::SeqCst);
        // Wake the blocking accept with a connection of our own.
        let mut wake = self.addr;
        if wake.ip().is_unspecified() {
            wake.set_ip(match wake {
                SocketAddr::V4(_) => std::net::Ipv4Addr::LOCALHOST.into(),
                SocketAddr::V6(_) => std::net::Ipv6Addr::LOCALHOST.into(),
            });
        }
        let _ = TcpStream::connect_timeout(&wake, Duration::from_secs(1));
        let _ = thread.join();
    }
}

impl Drop for ServerHandle {
    fn drop(&mut self) {
        self.shutdown();
    }
}

fn accept_loop(listener: TcpListener, store: Arc<Store>, config: ServerConfig, stop: Arc<AtomicBool>) {
    let active = Arc::new(AtomicUsize::new(0));
    let open: Arc<Mutex<Vec<(u64, TcpStream)>>> = Arc::new(Mutex::new(Vec::new()));
    let mut threads: Vec<JoinHandle<()>> = Vec::new();
    let mut next_id = 0u64;
    for incoming in listener.incoming() {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        threads.retain(|t| !t.is_finished());
        let stream = match incoming {
            Ok(s) => s,
            Err(_) => {
                // Out of file descriptors and the like: wait rather than spin.
                thread::sleep(Duration::from_millis(20));
                continue;
            }
        };
        let _ = stream.set_write_timeout(Some(config.timeout));
        let _ = stream.set_nodelay(true);
        if active.load(Ordering::SeqCst) >= config.max_clients {
            let busy = Reply::Error { code: ErrorCode::Busy, message: "too many clients; retry later".into() };
            let _ = write_frame(&mut &stream, &busy.encode());
            continue;
        }
        let id = next_id;
        next_id += 1;
        if let Ok(clone) = stream.try_clone() {
            lock(&open).push((id, clone));
        }
        active.fetch_add(1, Ordering::SeqCst);
        let (store, active2, open2) = (store.clone(), active.clone(), open.clone());
        let spawned = thread::Builder::new().name("taxel-device-conn".into()).spawn(move || {
            serve_connection(&stream, &store, config);
            let _ = stream.shutdown(Shutdown::Both);
            lock(&open2).retain(|(i, _)| *i != id);
            active2.fetch_sub(1, Ordering::SeqCst);
        });
        match spawned {
            Ok(t) => threads.push(t),
            Err(_) => {
                lock(&open).retain(|(i, _)| *i != id);
                active.fetch_sub(1, Ordering::SeqCst);
            }
        }
    }
    for (_, s) in lock(&open).iter() {
        let _ = s.shutdown(Shutdown::Both);
    }
    for t in threads {
        let _ = t.join();
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Reads from a socket with one deadline for a whole frame, however the
/// bytes are split, so a client sending a byte at a time still times out.
struct Deadline<'a> {
    stream: &'a TcpStream,
    until: Instant,
}

impl Read for Deadline<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let left = self.until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        self.stream.set_read_timeout(Some(left))?;
        let mut s = self.stream;
        s.read(buf)
    }
}

fn serve_connection(stream: &TcpStream, store: &Store, config: ServerConfig) {
    let mut session = Session { stream, store, config };
    session.run();
}

struct Session<'a> {
    stream: &'a TcpStream,
    store: &'a Store,
    config: ServerConfig,
}

/// What to do after a request.
enum Next {
    Continue,
    Close,
}

impl<'a> Session<'a> {
    fn next(&mut self) -> Result<Request, ProtocolError> {
        let mut r = Deadline { stream: self.stream, until: Instant::now() + self.config.timeout };
        let (kind, payload) = read_frame(&mut r)?;
        Request::decode(kind, payload)
    }

    fn send(&mut self, reply: &Reply) -> bool {
        let mut w: &TcpStream = self.stream;
        write_frame(&mut w, &reply.encode()).is_ok() && w.flush().is_ok()
    }

    fn refuse(&mut self, r: Refusal) -> bool {
        self.send(&Reply::Error { code: r.code, message: r.message })
    }

    fn protocol_error(&mut self, message: impl Into<String>) -> Next {
        self.send(&Reply::Error { code: ErrorCode::Protocol, message: message.into() });
        Next::Close
    }

    fn run(&mut self) {
        match self.next() {
            Ok(Request::Hello { version }) if version == PROTOCOL_VERSION => match self.store.info() {
                Ok(info) => {
                    if !self.send(&Reply::Welcome(info)) {
                        return;
                    }
                }
                Err(r) => {
                    self.refuse(r);
                    return;
                }
            },
            Ok(Request::Hello { version }) => {
                self.send(&Reply::Error {
                    code: ErrorCode::Version,
                    message: std::format!("this device speaks protocol {PROTOCOL_VERSION}, not {version}"),
                });
                return;
            }
            Ok(_) => {
                self.protocol_error("the first frame must be HELLO");
                return;
            }
            Err(e) => {
                self.report_read_error(e);
                return;
            }
        }
        // The upload in progress, if any. Dropping it (on any exit from this
        // loop) deletes its staging file and releases its reservation.
        let mut upload: Option<Upload<'a>> = None;
        loop {
            let req = match self.next() {
                Ok(r) => r,
                Err(e) => {
                    self.report_read_error(e);
                    return;
                }
            };
            if let Next::Close = self.handle(req, &mut upload) {
                return;
            }
        }
    }

    fn report_read_error(&mut self, e: ProtocolError) {
        match e {
            ProtocolError::Timeout => {
                self.send(&Reply::Error { code: ErrorCode::Timeout, message: "no complete frame in time".into() });
            }
            ProtocolError::UnknownKind(_) | ProtocolError::TooLarge(_) | ProtocolError::Malformed(_) => {
                self.protocol_error(std::format!("{e}"));
            }
            ProtocolError::Closed | ProtocolError::Truncated | ProtocolError::Io(_) => {}
        }
    }

    fn handle(&mut self, req: Request, upload: &mut Option<Upload<'a>>) -> Next {
        match req {
            Request::Offer(offer) => {
                if upload.is_some() {
                    return self.protocol_error("an offer while another bundle is being sent");
                }
                match self.store.begin(&offer) {
                    Ok(u) => {
                        *upload = Some(u);
                        self.reply(Reply::Ready)
                    }
                    Err(r) => self.reply_refusal(r),
                }
            }
            Request::Data(data) => {
                let Some(u) = upload.as_mut() else {
                    return self.protocol_error("data without an accepted offer");
                };
                match u.write(&data) {
                    Ok(()) => Next::Continue,
                    Err(r) => {
                        // The client is streaming blindly; after a refusal
                        // here the rest of its data has no meaning.
                        self.refuse(r);
                        Next::Close
                    }
                }
            }
            Request::Commit => {
                let Some(u) = upload.take() else {
                    return self.protocol_error("commit without an accepted offer");
                };
                match u.commit() {
                    Ok(entry) => self.reply(Reply::Verified(entry)),
                    Err(r) => self.reply_refusal(r),
                }
            }
            Request::List => match self.store.list() {
                Ok(entries) => self.reply(Reply::Listing(entries)),
                Err(r) => self.reply_refusal(r),
            },
            Request::Delete { name } => {
                if upload.is_some() {
                    return self.protocol_error("a delete while a bundle is being sent");
                }
                match self.store.delete(&name) {
                    Ok(()) => self.reply(Reply::Deleted),
                    Err(r) => self.reply_refusal(r),
                }
            }
            Request::Hello { .. } => self.protocol_error("a second HELLO"),
            Request::Bye => Next::Close,
        }
    }

    fn reply(&mut self, r: Reply) -> Next {
        if self.send(&r) { Next::Continue } else { Next::Close }
    }

    fn reply_refusal(&mut self, r: Refusal) -> Next {
        if self.refuse(r) { Next::Continue } else { Next::Close }
    }
}
