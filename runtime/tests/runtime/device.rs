//! The device simulator and the loader: transfers cut at every byte,
//! corrupted bytes, wrong profiles, a full device, concurrent and stalled
//! clients. After each, every bundle in the store validates and nothing
//! previously stored is lost. Servers listen on 127.0.0.1 port 0 and stop
//! when their handle drops; every wait has a timeout.

use std::fs;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::time::{Duration, Instant};

use taxel_format::{Bundle, BundleView, Manifest, profiles};
use taxel_runtime::device::protocol::{PROTOCOL_VERSION, read_frame};
use taxel_runtime::device::{
    Client, ErrorCode, Offer, Reply, Request, STAGING_PREFIX, Server, ServerConfig, ServerHandle, Store, StoreConfig,
    checksum,
};

const WAIT: Duration = Duration::from_secs(5);

/// A valid bundle for `profile`, made distinct by `mark` (its content hash).
fn bundle(profile: &str, mark: u8) -> Vec<u8> {
    let mut m = Manifest::new(profiles::builtin(profile).unwrap());
    m.content_hash = [mark; 32];
    Bundle::new(m).to_bytes().unwrap()
}

fn serve(dir: &Path, profile: Option<&str>, capacity: Option<u64>, config: ServerConfig) -> ServerHandle {
    let store =
        Store::open(dir, StoreConfig { profile: profile.map(Into::into), capacity, stale_staging: None }).unwrap();
    Server::bind("127.0.0.1:0", store, config).unwrap().spawn().unwrap()
}

fn quick() -> ServerConfig {
    ServerConfig { timeout: Duration::from_secs(2), max_clients: 8 }
}

fn client(addr: SocketAddr) -> Client {
    Client::connect(&addr.to_string(), WAIT).unwrap()
}

/// Every bundle in `dir` validates, no staging file is left, and each of
/// `expected` is stored with exactly its bytes.
fn assert_consistent(dir: &Path, expected: &[(&str, &[u8])]) {
    for entry in fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().into_string().unwrap();
        assert!(!name.starts_with(STAGING_PREFIX), "staging file {name} left behind");
        let bytes = fs::read(entry.path()).unwrap();
        assert!(BundleView::parse(&bytes).is_ok(), "{name} does not validate");
    }
    for (name, bytes) in expected {
        assert_eq!(fs::read(dir.join(name)).unwrap(), *bytes, "{name} changed or lost");
    }
}

/// A raw protocol connection for tests that must misbehave.
struct Raw(TcpStream);

impl Raw {
    fn connect(addr: SocketAddr) -> Raw {
        let s = TcpStream::connect_timeout(&addr, WAIT).unwrap();
        s.set_read_timeout(Some(WAIT)).unwrap();
        s.set_write_timeout(Some(WAIT)).unwrap();
        Raw(s)
    }
    fn send(&mut self, r: &Request) {
        self.0.write_all(&r.encode()).unwrap();
    }
    fn reply(&mut self) -> Reply {
        let (k, p) = read_frame(&mut self.0).unwrap();
        Reply::decode(k, &p).unwrap()
    }
    fn hello(addr: SocketAddr) -> Raw {
        let mut r = Raw::connect(addr);
        r.send(&Request::Hello { version: PROTOCOL_VERSION });
        assert!(matches!(r.reply(), Reply::Welcome(_)));
        r
    }
}

fn offer(name: &str, profile: &str, bytes: &[u8]) -> Request {
    Request::Offer(Offer {
        name: name.into(),
        profile: profile.into(),
        size: bytes.len() as u64,
        checksum: checksum(bytes),
    })
}

fn code(r: Reply) -> ErrorCode {
    match r {
        Reply::Error { code, .. } => code,
        other => panic!("expected an error, got {other:?}"),
    }
}

/// A whole load session as the bytes a client sends, with the data split
/// into three frames so that cuts fall inside and between data frames.
fn session_bytes(name: &str, bytes: &[u8]) -> Vec<u8> {
    let mut out = Request::Hello { version: PROTOCOL_VERSION }.encode();
    out.extend(offer(name, "stress2", bytes).encode());
    let third = bytes.len().div_ceil(3);
    for chunk in bytes.chunks(third) {
        out.extend(Request::Data(chunk.to_vec()).encode());
    }
    out.extend(Request::Commit.encode());
    out
}

#[test]
fn load_list_and_delete_through_the_client() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let a = bundle("stress2", 1);
    let mut c = client(server.addr());
    assert_eq!(c.info().profile, "stress2");
    let entry = c.load("a.taxel", &a).unwrap();
    assert_eq!((entry.size, entry.checksum), (a.len() as u64, *blake3::hash(&a).as_bytes()));
    assert_eq!(c.list().unwrap(), vec![entry]);
    c.delete("a.taxel").unwrap();
    assert!(c.list().unwrap().is_empty());
    assert_eq!(c.delete("a.taxel").unwrap_err().code(), Some(ErrorCode::NotFound));
    c.bye();
    server.stop();
    assert_consistent(dir.path(), &[]);
}

#[test]
fn a_newer_bundle_replaces_the_old_one_only_when_verified() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let (old, new) = (bundle("stress2", 1), bundle("stress2", 2));
    client(server.addr()).load("map.taxel", &old).unwrap();
    client(server.addr()).load("map.taxel", &new).unwrap();
    server.stop();
    assert_consistent(dir.path(), &[("map.taxel", &new)]);
}

#[test]
fn a_connection_cut_at_any_byte_leaves_the_old_bundle_intact() {
    let dir = tempfile::tempdir().unwrap();
    let (old, new) = (bundle("stress2", 1), bundle("stress2", 2));
    let server = serve(dir.path(), Some("stress2"), None, quick());
    client(server.addr()).load("map.taxel", &old).unwrap();
    let stream = session_bytes("map.taxel", &new);
    for k in 0..stream.len() {
        let mut s = Raw::connect(server.addr());
        s.0.write_all(&stream[..k]).unwrap();
        drop(s);
        assert_consistent_but_staging(dir.path(), &old);
    }
    // Every cut session has ended; none left a staging file behind.
    server.stop();
    assert_consistent(dir.path(), &[("map.taxel", &old)]);
    // The whole session, sent without reading a reply, does replace it.
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let mut s = Raw::connect(server.addr());
    s.0.write_all(&stream).unwrap();
    let replies: Vec<Reply> = (0..3).map(|_| s.reply()).collect();
    assert!(matches!(replies[2], Reply::Verified(_)), "{replies:?}");
    drop(s);
    server.stop();
    assert_consistent(dir.path(), &[("map.taxel", &new)]);
}

/// Like `assert_consistent`, while a cut session may still be cleaning up.
fn assert_consistent_but_staging(dir: &Path, old: &[u8]) {
    for entry in fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().into_string().unwrap();
        if !name.starts_with(STAGING_PREFIX) {
            assert!(BundleView::parse(&fs::read(entry.path()).unwrap()).is_ok(), "{name} does not validate");
        }
    }
    assert_eq!(fs::read(dir.join("map.taxel")).unwrap(), old);
}

#[test]
fn a_corrupted_byte_is_caught_by_the_checksum_or_the_validator() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let (old, new) = (bundle("stress2", 1), bundle("stress2", 2));
    client(server.addr()).load("map.taxel", &old).unwrap();
    let mut s = Raw::hello(server.addr());
    for i in (0..new.len()).step_by(7) {
        let mut bad = new.clone();
        bad[i] ^= 0x10;
        // Corrupted in transit: the offered checksum is of the good bytes.
        s.send(&offer("map.taxel", "stress2", &new));
        assert_eq!(s.reply(), Reply::Ready);
        s.send(&Request::Data(bad.clone()));
        s.send(&Request::Commit);
        assert_eq!(code(s.reply()), ErrorCode::ChecksumMismatch, "byte {i}");
        // Corrupted before sending: the checksum matches but the bundle does not validate.
        s.send(&offer("map.taxel", "stress2", &bad));
        assert_eq!(s.reply(), Reply::Ready);
        s.send(&Request::Data(bad));
        s.send(&Request::Commit);
        assert_eq!(code(s.reply()), ErrorCode::InvalidBundle, "byte {i}");
    }
    drop(s);
    server.stop();
    assert_consistent(dir.path(), &[("map.taxel", &old)]);
}

#[test]
fn a_bundle_for_another_profile_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let old = bundle("stress2", 1);
    client(server.addr()).load("map.taxel", &old).unwrap();
    let other = bundle("finger3", 2);
    // The client refuses before sending.
    let e = client(server.addr()).load("map.taxel", &other).unwrap_err();
    assert_eq!(e.code(), Some(ErrorCode::WrongProfile));
    // A client that lies about the profile in its offer is caught on commit.
    let mut s = Raw::hello(server.addr());
    s.send(&offer("map.taxel", "finger3", &other));
    assert_eq!(code(s.reply()), ErrorCode::WrongProfile);
    s.send(&offer("map.taxel", "stress2", &other));
    assert_eq!(s.reply(), Reply::Ready);
    s.send(&Request::Data(other));
    s.send(&Request::Commit);
    assert_eq!(code(s.reply()), ErrorCode::WrongProfile);
    drop(s);
    server.stop();
    assert_consistent(dir.path(), &[("map.taxel", &old)]);
}

#[test]
fn a_full_device_refuses_and_keeps_what_it_has() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (bundle("stress2", 1), bundle("stress2", 2));
    // Room for one bundle and a bit, not for two.
    let capacity = a.len() as u64 + a.len() as u64 / 2;
    let server = serve(dir.path(), Some("stress2"), Some(capacity), quick());
    let mut c = client(server.addr());
    assert_eq!(c.info().free, capacity);
    c.load("a.taxel", &a).unwrap();
    assert_eq!(c.load("b.taxel", &b).unwrap_err().code(), Some(ErrorCode::NoSpace));
    // Replacing needs room for the new bundle beside the old one.
    assert_eq!(c.load("a.taxel", &b).unwrap_err().code(), Some(ErrorCode::NoSpace));
    c.delete("a.taxel").unwrap();
    c.load("b.taxel", &b).unwrap();
    drop(c);
    server.stop();
    assert_consistent(dir.path(), &[("b.taxel", &b)]);
}

#[test]
fn two_clients_loading_at_once_are_served_or_told_to_retry() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), Some("stress2"), None, quick());
    let (a, b) = (bundle("stress2", 1), bundle("stress2", 2));
    // The same name: the second offer is told to retry while the first is in flight.
    let mut first = Raw::hello(server.addr());
    first.send(&offer("map.taxel", "stress2", &a));
    assert_eq!(first.reply(), Reply::Ready);
    first.send(&Request::Data(a[..10].to_vec()));
    let e = client(server.addr()).load("map.taxel", &b).unwrap_err();
    assert_eq!(e.code(), Some(ErrorCode::Busy));
    first.send(&Request::Data(a[10..].to_vec()));
    first.send(&Request::Commit);
    assert!(matches!(first.reply(), Reply::Verified(_)));
    // Different names at the same time: both stored.
    let addr = server.addr();
    let handles: Vec<_> = (0..4u8)
        .map(|i| {
            std::thread::spawn(move || {
                let bytes = bundle("stress2", 10 + i);
                client(addr).load(&format!("b{i}.taxel"), &bytes).unwrap();
                bytes
            })
        })
        .collect();
    let loaded: Vec<Vec<u8>> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    drop(first);
    server.stop();
    let names: Vec<String> = (0..4).map(|i| format!("b{i}.taxel")).collect();
    let mut expected: Vec<(&str, &[u8])> = vec![("map.taxel", &a)];
    expected.extend(names.iter().zip(&loaded).map(|(n, b)| (n.as_str(), b.as_slice())));
    assert_consistent(dir.path(), &expected);
}

#[test]
fn a_client_beyond_the_limit_is_told_to_retry() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), None, None, ServerConfig { timeout: Duration::from_secs(2), max_clients: 1 });
    let _first = Raw::hello(server.addr());
    let e = Client::connect(&server.addr().to_string(), WAIT).unwrap_err();
    assert_eq!(e.code(), Some(ErrorCode::Busy));
}

#[test]
fn a_stalled_or_trickling_client_is_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let timeout = Duration::from_millis(300);
    let server = serve(dir.path(), None, None, ServerConfig { timeout, max_clients: 8 });
    let a = bundle("stress2", 1);
    // Stalled after an accepted offer: timed out, staging file removed.
    let mut s = Raw::hello(server.addr());
    s.send(&offer("a.taxel", "stress2", &a));
    assert_eq!(s.reply(), Reply::Ready);
    let started = Instant::now();
    assert_eq!(code(s.reply()), ErrorCode::Timeout);
    assert!(started.elapsed() < WAIT);
    let mut rest = Vec::new();
    assert_eq!(s.0.read_to_end(&mut rest).unwrap(), 0, "the device closes the connection");
    // Trickling a frame one byte at a time does not reset the clock.
    let mut t = Raw::hello(server.addr());
    let frame = offer("b.taxel", "stress2", &a).encode();
    let mut timed_out = false;
    for byte in &frame {
        if t.0.write_all(&[*byte]).is_err() {
            timed_out = true;
            break;
        }
        std::thread::sleep(timeout / 4);
    }
    timed_out |= matches!(t.reply(), Reply::Error { code: ErrorCode::Timeout, .. });
    assert!(timed_out);
    server.stop();
    assert_consistent(dir.path(), &[]);
}

#[test]
fn names_that_could_leave_the_store_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let store_dir = dir.path().join("store");
    let server = serve(&store_dir, None, None, quick());
    let a = bundle("stress2", 1);
    let mut s = Raw::hello(server.addr());
    for name in ["../escape.taxel", "sub/x.taxel", ".hidden", "", "..", "a\\b"] {
        s.send(&offer(name, "stress2", &a));
        assert_eq!(code(s.reply()), ErrorCode::InvalidName, "{name:?}");
        s.send(&Request::Delete { name: name.into() });
        assert_eq!(code(s.reply()), ErrorCode::InvalidName, "{name:?}");
    }
    drop(s);
    server.stop();
    assert!(!dir.path().join("escape.taxel").exists());
    assert_consistent(&store_dir, &[]);
}

#[test]
fn protocol_violations_close_the_session_without_harm() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(dir.path(), None, None, quick());
    // Data before hello.
    let mut s = Raw::connect(server.addr());
    s.send(&Request::Data(vec![1, 2, 3]));
    assert_eq!(code(s.reply()), ErrorCode::Protocol);
    // A wrong version.
    let mut s = Raw::connect(server.addr());
    s.send(&Request::Hello { version: PROTOCOL_VERSION + 1 });
    assert_eq!(code(s.reply()), ErrorCode::Version);
    // More data than offered.
    let a = bundle("stress2", 1);
    let mut s = Raw::hello(server.addr());
    s.send(&offer("a.taxel", "stress2", &a));
    assert_eq!(s.reply(), Reply::Ready);
    let mut more = a.clone();
    more.push(0);
    s.send(&Request::Data(more));
    assert_eq!(code(s.reply()), ErrorCode::SizeMismatch);
    // A frame claiming to be huge.
    let mut s = Raw::hello(server.addr());
    s.0.write_all(&[0x03, 0xff, 0xff, 0xff, 0x7f]).unwrap();
    assert_eq!(code(s.reply()), ErrorCode::Protocol);
    server.stop();
    assert_consistent(dir.path(), &[]);
}

#[test]
fn a_mounted_folder_store_puts_atomically_and_checks_the_profile() {
    let dir = tempfile::tempdir().unwrap();
    let config =
        StoreConfig { profile: Some("stress2".into()), capacity: None, stale_staging: Some(Duration::from_secs(600)) };
    let store = Store::open(dir.path(), config).unwrap();
    let a = bundle("stress2", 1);
    store.put("a.taxel", &a).unwrap();
    assert_eq!(store.put("a.taxel", &bundle("finger3", 2)).unwrap_err().code, ErrorCode::WrongProfile);
    let mut broken = bundle("stress2", 3);
    broken.truncate(broken.len() - 1);
    assert_eq!(store.put("a.taxel", &broken).unwrap_err().code, ErrorCode::InvalidBundle);
    assert_consistent(dir.path(), &[("a.taxel", &a)]);
}
