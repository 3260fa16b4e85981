//! What keeps a local server that accepts files safe: requests must name
//! the studio's own host (DNS rebinding) and come from its own origin
//! (CSRF); paths stay inside the opened folder; every response forbids
//! scripts from anywhere else.

use std::path::{Component, Path, PathBuf};

/// The headers every response carries: the page runs only its own scripts
/// (and compiles the embedded WASM module), loads nothing from elsewhere,
/// and cannot be framed.
pub const HEADERS: &[(&str, &str)] = &[
    (
        "Content-Security-Policy",
        "default-src 'none'; script-src 'self' 'wasm-unsafe-eval'; style-src 'self'; img-src 'self' blob: data:; \
         connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'",
    ),
    ("X-Content-Type-Options", "nosniff"),
    ("Referrer-Policy", "no-referrer"),
    ("Cross-Origin-Resource-Policy", "same-origin"),
    ("Cross-Origin-Opener-Policy", "same-origin"),
    ("X-Frame-Options", "DENY"),
    ("Cache-Control", "no-store"),
];

/// The `Host` values the studio answers to: its address and, on loopback,
/// `localhost`, each with the port.
#[derive(Debug, Clone)]
pub struct Hosts {
    allowed: Vec<String>,
}

impl Hosts {
    /// The hosts of a server bound to `addr`.
    pub fn new(addr: std::net::SocketAddr) -> Self {
        let port = addr.port();
        let mut allowed = vec![match addr.ip() {
            std::net::IpAddr::V4(ip) => format!("{ip}:{port}"),
            std::net::IpAddr::V6(ip) => format!("[{ip}]:{port}"),
        }];
        if addr.ip().is_loopback() {
            allowed.extend([format!("localhost:{port}"), format!("127.0.0.1:{port}"), format!("[::1]:{port}")]);
        }
        allowed.dedup();
        Hosts { allowed }
    }

    /// Why a request with these `Host` and `Origin` headers is refused, or
    /// `None` when it is the studio's own: the host must be one of ours, and
    /// an origin, when the browser sends one, `http://` and one of ours.
    pub fn refusal(&self, host: Option<&str>, origin: Option<&str>) -> Option<&'static str> {
        let ours = |h: &str| self.allowed.iter().any(|a| a.eq_ignore_ascii_case(h));
        match host {
            Some(h) if ours(h) => {}
            _ => return Some("the request's Host is not this studio's"),
        }
        match origin {
            None => None,
            Some(o) if o.strip_prefix("http://").is_some_and(ours) => None,
            Some(_) => Some("the request's Origin is not this studio's"),
        }
    }
}

/// The file at `rel` (a relative path from the page, `/`-separated, already
/// percent-decoded) inside `root`, refused when it leaves the folder: an
/// absolute path, `..`, a drive or scheme, a backslash, or a symbolic link
/// that points outside. `root` must be canonical.
pub fn inside(root: &Path, rel: &str) -> Result<PathBuf, String> {
    if rel.is_empty() || rel.contains(['\\', ':', '\0']) {
        return Err(format!("'{rel}' is not a relative path in the opened folder"));
    }
    let rel_path = Path::new(rel);
    if rel_path.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(format!("'{rel}' leaves the opened folder"));
    }
    let full = root.join(rel_path);
    // Symbolic links may still point elsewhere: compare the real paths.
    let real = full.canonicalize().map_err(|e| format!("cannot open '{rel}': {e}"))?;
    if !real.starts_with(root) {
        return Err(format!("'{rel}' lies outside the opened folder"));
    }
    Ok(real)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_studio_s_own_host_and_origin_pass() {
        let h = Hosts::new("127.0.0.1:4000".parse().unwrap());
        assert_eq!(h.refusal(Some("127.0.0.1:4000"), None), None);
        assert_eq!(h.refusal(Some("localhost:4000"), Some("http://localhost:4000")), None);
        assert!(h.refusal(Some("evil.example:4000"), None).is_some());
        assert!(h.refusal(None, None).is_some());
        assert!(h.refusal(Some("127.0.0.1:4001"), None).is_some());
        assert!(h.refusal(Some("127.0.0.1:4000"), Some("http://evil.example")).is_some());
        assert!(h.refusal(Some("127.0.0.1:4000"), Some("null")).is_some());
        assert!(h.refusal(Some("127.0.0.1:4000"), Some("https://127.0.0.1:4000")).is_some());
    }

    #[test]
    fn paths_stay_inside_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().canonicalize().unwrap();
        std::fs::create_dir(root.join("sub")).unwrap();
        std::fs::write(root.join("sub/a.svg"), "<svg/>").unwrap();
        assert_eq!(inside(&root, "sub/a.svg").unwrap(), root.join("sub/a.svg"));
        assert_eq!(inside(&root, "./sub/a.svg").unwrap(), root.join("sub/a.svg"));
        for bad in ["../x", "sub/../../x", "/etc/passwd", "C:/x", "sub\\a.svg", "", "a\0b"] {
            assert!(inside(&root, bad).is_err(), "{bad}");
        }
        #[cfg(unix)]
        {
            let outside = tempfile::tempdir().unwrap();
            std::fs::write(outside.path().join("secret.svg"), "<svg/>").unwrap();
            std::os::unix::fs::symlink(outside.path().join("secret.svg"), root.join("link.svg")).unwrap();
            assert!(inside(&root, "link.svg").unwrap_err().contains("outside"));
        }
    }
}
