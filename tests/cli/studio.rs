//! `taxel studio` against the running server on 127.0.0.1 (an ephemeral
//! port): what it serves, what it refuses (other hosts and origins, paths
//! outside the opened folder, uploads past the input limit), that a
//! malformed file is the CLI's diagnostic and the server keeps serving, that
//! the bundle downloaded is `taxel build`'s byte for byte, and that the WASM
//! module it embeds plays a long trace frame for frame as the native runtime.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

const MAP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");

/// A studio serving a folder, stopped when dropped.
pub struct Studio {
    child: Child,
    pub port: u16,
}

impl Studio {
    pub fn start(path: &Path) -> Studio {
        let mut child = Command::new(env!("CARGO_BIN_EXE_taxel"))
            .args(["studio", path.to_str().unwrap(), "--no-open", "--port", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap()).read_line(&mut line).unwrap();
        let url = line.split_whitespace().find(|w| w.starts_with("http://")).unwrap_or_else(|| panic!("{line}"));
        let port = url.trim_end_matches('/').rsplit(':').next().unwrap().parse().unwrap();
        Studio { child, port }
    }

    pub fn host(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// One request with our own Host; `extra` headers may replace it.
    pub fn request(&self, method: &str, path: &str, extra: &[(&str, &str)], body: &[u8]) -> Reply {
        let mut s = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        let host = self.host();
        let mut head = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\nContent-Length: {}\r\n", body.len());
        if !extra.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
            head += &format!("Host: {host}\r\n");
        }
        for (k, v) in extra {
            head += &format!("{k}: {v}\r\n");
        }
        head += "\r\n";
        s.write_all(head.as_bytes()).unwrap();
        s.write_all(body).unwrap();
        read_reply(s)
    }

    pub fn get(&self, path: &str) -> Reply {
        self.request("GET", path, &[], b"")
    }

    pub fn post(&self, path: &str, body: &[u8]) -> Reply {
        let origin = format!("http://{}", self.host());
        self.request("POST", path, &[("Origin", &origin)], body)
    }
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A response: status, headers (lower-case names) and body.
pub struct Reply {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Reply {
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    pub fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&self.body)))
    }
}

fn read_reply(mut s: TcpStream) -> Reply {
    let mut all = Vec::new();
    s.read_to_end(&mut all).unwrap();
    let split = all.windows(4).position(|w| w == b"\r\n\r\n").expect("a header");
    let head = String::from_utf8_lossy(&all[..split]).into_owned();
    let mut lines = head.split("\r\n");
    let status = lines.next().unwrap().split_whitespace().nth(1).unwrap().parse().unwrap();
    let headers: Vec<(String, String)> = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_string()))
        .collect();
    let mut body = all[split + 4..].to_vec();
    if headers.iter().any(|(k, v)| k == "transfer-encoding" && v.contains("chunked")) {
        body = unchunk(&body);
    }
    Reply { status, headers, body }
}

fn unchunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let end = b.windows(2).position(|w| w == b"\r\n").unwrap();
        let len = usize::from_str_radix(std::str::from_utf8(&b[..end]).unwrap().trim(), 16).unwrap();
        if len == 0 {
            return out;
        }
        out.extend_from_slice(&b[end + 2..end + 2 + len]);
        b = &b[end + 4 + len..];
    }
}

fn folder() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("maps");
    std::fs::create_dir(&root).unwrap();
    std::fs::copy(MAP, root.join("tala-map.svg")).unwrap();
    (dir, root)
}

fn taxel(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

#[test]
fn the_page_and_its_assets_come_from_the_binary_with_a_strict_policy() {
    let (_dir, root) = folder();
    let s = Studio::start(&root);
    let page = s.get("/");
    assert_eq!(page.status, 200);
    let html = String::from_utf8(page.body.clone()).unwrap();
    assert!(html.contains("taxel studio") && html.contains("/studio.js"), "{html}");
    // Nothing in the page comes from elsewhere.
    assert!(!html.contains("http://") && !html.contains("https://"));
    let csp = page.header("content-security-policy").unwrap();
    assert!(csp.contains("default-src 'none'") && csp.contains("script-src 'self'"), "{csp}");
    for asset in ["/studio.js", "/player.js", "/studio.css"] {
        let r = s.get(asset);
        assert_eq!(r.status, 200, "{asset}");
        assert!(!String::from_utf8_lossy(&r.body).contains("https://"), "{asset} loads nothing from the internet");
    }
    let wasm = s.get("/taxel.wasm");
    assert_eq!(wasm.header("content-type"), Some("application/wasm"));
    assert!(wasm.body.starts_with(b"\0asm"));
    let start = s.get("/api/start").json();
    assert_eq!(start["files"], serde_json::json!(["tala-map.svg"]));
    assert!(start["profiles"].as_array().unwrap().iter().any(|p| p == "stress2"));
}

#[test]
fn requests_for_another_host_or_from_another_origin_are_refused() {
    let (_dir, root) = folder();
    let s = Studio::start(&root);
    // DNS rebinding: the browser sends the attacker's name as Host.
    assert_eq!(s.request("GET", "/api/start", &[("Host", "evil.example:80")], b"").status, 403);
    assert_eq!(s.request("GET", "/", &[("Host", &format!("evil.example:{}", s.port))], b"").status, 403);
    // CSRF: another page posts to the studio.
    let open = "/api/open?path=tala-map.svg";
    assert_eq!(s.request("POST", open, &[("Origin", "http://evil.example")], b"").status, 403);
    assert_eq!(s.request("POST", open, &[("Origin", "null")], b"").status, 403);
    // Our own name and origin pass, `localhost` too.
    let localhost = format!("localhost:{}", s.port);
    assert_eq!(s.request("GET", "/api/start", &[("Host", &localhost)], b"").status, 200);
    assert_eq!(s.post(open, b"").status, 200);
}

#[test]
fn no_path_outside_the_opened_folder_is_read() {
    let (dir, root) = folder();
    std::fs::write(
        dir.path().join("secret.svg"),
        "<svg xmlns='http://www.w3.org/2000/svg'><title>SECRET</title></svg>",
    )
    .unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(dir.path().join("secret.svg"), root.join("link.svg")).unwrap();
    let s = Studio::start(&root);
    let secret = dir.path().join("secret.svg");
    let absolute = format!("/api/open?path={}", secret.display());
    for path in [
        "/api/open?path=../secret.svg",
        "/api/open?path=%2e%2e%2fsecret.svg",
        "/api/open?path=%2E%2E/secret.svg",
        "/api/open?path=..%5csecret.svg",
        "/api/open?path=%2Fetc%2Fpasswd",
        "/api/open?path=/etc/passwd",
        absolute.as_str(),
        "/api/open?path=link.svg",
    ] {
        let r = s.post(path, b"");
        assert_eq!(r.status, 403, "{path}: {}", String::from_utf8_lossy(&r.body));
        assert!(!String::from_utf8_lossy(&r.body).contains("SECRET"), "{path}");
    }
    // No file is served by its path at all.
    for path in ["/../secret.svg", "/%2e%2e/secret.svg", "/tala-map.svg", "/etc/passwd"] {
        assert_eq!(s.get(path).status, 404, "{path}");
    }
    // The folder's own file opens.
    assert_eq!(s.post("/api/open?path=tala-map.svg", b"").status, 200);
}

#[test]
fn an_upload_past_the_input_limit_is_refused_before_it_is_read() {
    let (_dir, root) = folder();
    let s = Studio::start(&root);
    let mut c = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
    let head = format!(
        "POST /api/build?name=big.svg HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: {}\r\n\r\n",
        s.host(),
        (64u64 << 20) + 1
    );
    c.write_all(head.as_bytes()).unwrap();
    c.write_all(&[b' '; 4096]).unwrap();
    let r = read_reply(c);
    assert_eq!(r.status, 413);
    assert!(r.json()["error"].as_str().unwrap().contains("64 MB input limit"));
    assert_eq!(s.get("/api/start").status, 200, "the server keeps serving");
}

#[test]
fn a_malformed_file_gets_the_cli_s_diagnostic_and_the_server_keeps_serving() {
    let (dir, root) = folder();
    let s = Studio::start(&root);
    let bad = b"<svg xmlns='http://www.w3.org/2000/svg'><rect";
    let r = s.post("/api/build?name=broken.svg", bad);
    assert_eq!(r.status, 200);
    let v = r.json();
    assert!(v["errors"].as_u64().unwrap() >= 1, "{v}");
    assert!(v["bundle"].is_null());
    // The lines are `taxel check`'s for the same file.
    let file = dir.path().join("broken.svg");
    std::fs::write(&file, bad).unwrap();
    let o = taxel(&["check", file.to_str().unwrap()]);
    let cli = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
        .replace(file.to_str().unwrap(), "broken.svg");
    let first = v["groups"][0]["lines"][0].as_str().unwrap();
    assert!(cli.contains(first), "studio: {first}\ncli: {cli}");
    // Not a bundle either, and not even a known kind.
    let v = s.post("/api/build?name=x.taxel", b"TAXL garbage").json();
    assert!(v["groups"][0]["lines"][0].as_str().unwrap().contains("not a valid taxel bundle"), "{v}");
    assert_eq!(s.get("/").status, 200, "the server keeps serving");
    assert_eq!(s.post("/api/open?path=tala-map.svg", b"").json()["errors"], 0);
}

#[test]
fn the_bundle_downloaded_is_taxel_build_s_byte_for_byte() {
    let (dir, root) = folder();
    let s = Studio::start(&root);
    for (query, args) in
        [("", vec![]), ("&profile=stress2", vec!["-p", "stress2"]), ("&profile=dotpad", vec!["-p", "dotpad"])]
    {
        let v = s.post(&format!("/api/open?path=tala-map.svg{query}"), b"").json();
        let bundle = s.get(&format!("{}bundle", v["base"].as_str().unwrap()));
        assert_eq!(bundle.status, 200);
        assert!(bundle.header("content-disposition").unwrap().contains("tala-map.taxel"));
        let out = dir.path().join("cli.taxel");
        let mut a = vec!["build", MAP, "-o", out.to_str().unwrap()];
        a.extend(args);
        let o = taxel(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(std::fs::read(&out).unwrap() == bundle.body, "{query}: the studio's bundle differs from taxel build's");
        // The pictures are PNG; a pin display's exports are `taxel export`'s.
        let base = v["base"].as_str().unwrap();
        assert!(s.get(&format!("{base}preview.png")).body.starts_with(b"\x89PNG"));
        assert!(s.get(&format!("{base}drawing.png")).body.starts_with(b"\x89PNG"));
        if query.contains("dotpad") {
            let unicode = s.get(&format!("{base}export/unicode"));
            let txt = dir.path().join("cli.txt");
            assert!(
                taxel(&["export", out.to_str().unwrap(), "--format", "unicode", "-o", txt.to_str().unwrap()])
                    .status
                    .success()
            );
            assert_eq!(unicode.body, std::fs::read(&txt).unwrap());
        }
    }
}

#[test]
fn every_page_of_the_key_downloaded_is_taxel_build_s_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("maps");
    std::fs::create_dir(&root).unwrap();
    // Eight textures with long names: more than one page of `stress2`'s key.
    std::fs::write(root.join("regions.svg"), crate::key::long_key()).unwrap();
    let s = Studio::start(&root);
    let v = s.post("/api/open?path=regions.svg&profile=stress2", b"").json();
    let pages = v["bundle"]["key"].as_u64().unwrap() as usize;
    assert!(pages >= 2, "{v}");
    let out = dir.path().join("cli/regions.taxel");
    let o = taxel(&["build", root.join("regions.svg").to_str().unwrap(), "-p", "stress2", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let base = v["base"].as_str().unwrap();
    for k in 1..=pages {
        let (part, file) = if k == 1 {
            ("key".to_string(), "regions.key.taxel".to_string())
        } else {
            (format!("key{k}"), format!("regions.key{k}.taxel"))
        };
        let got = s.get(&format!("{base}{part}"));
        assert_eq!(got.status, 200, "{part}");
        assert!(
            got.header("content-disposition").unwrap().contains(&file),
            "{part}: {:?}",
            got.header("content-disposition")
        );
        assert!(
            std::fs::read(dir.path().join("cli").join(&file)).unwrap() == got.body,
            "{part}: the studio's page differs from taxel build's"
        );
    }
    assert_eq!(s.get(&format!("{base}key{}", pages + 1)).status, 404);
    assert_eq!(s.get(&format!("{base}key1")).status, 404, "the first page is `key`");
}

#[test]
fn a_drawing_is_never_sent_to_the_page_as_markup() {
    let (_dir, root) = folder();
    std::fs::write(
        root.join("evil.svg"),
        "<svg xmlns='http://www.w3.org/2000/svg' width='50mm' height='30mm' viewBox='0 0 50 30' onload='alert(1)'>\
         <script>alert(2)</script><foreignObject><div xmlns='http://www.w3.org/1999/xhtml'>x</div></foreignObject>\
         <rect id='r' x='5' y='5' width='20' height='10' fill='red' onclick='alert(3)'/></svg>",
    )
    .unwrap();
    let s = Studio::start(&root);
    let v = s.post("/api/open?path=evil.svg", b"").json();
    let base = v["base"].as_str().unwrap().to_string();
    let drawing = s.get(&format!("{base}drawing.png"));
    assert_eq!(drawing.header("content-type"), Some("image/png"));
    assert!(!v.to_string().contains("alert"), "{v}");
    // The copy is only ever a download, and sandboxed should a browser show it.
    let copy = s.get(&format!("{base}copy.svg"));
    assert!(copy.header("content-disposition").unwrap().starts_with("attachment"));
    assert_eq!(copy.header("content-security-policy"), Some("sandbox"));
}

#[test]
fn a_style_change_rebuilds_a_copy_and_saves_it_beside_the_original_only_when_asked() {
    let (_dir, root) = folder();
    let original = std::fs::read(root.join("tala-map.svg")).unwrap();
    let s = Studio::start(&root);
    let v = s.post("/api/open?path=tala-map.svg", b"").json();
    let base = v["base"].as_str().unwrap().to_string();
    let before = s.get(&format!("{base}bundle")).body;
    let r = s.post(&format!("{base}restyle?element=path1&style={}", "dots(radius%3A%201mm)"), b"");
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let v2 = r.json();
    let base2 = v2["base"].as_str().unwrap().to_string();
    let after = s.get(&format!("{base2}bundle")).body;
    assert_ne!(before, after, "the style change changed the bundle");
    let copy = String::from_utf8(s.get(&format!("{base2}copy.svg")).body).unwrap();
    assert!(copy.contains("data-tactile=\"dots(radius: 1mm)\""), "{copy}");
    // The bundle is `taxel build`'s of the copy.
    let copy_file = root.join("copy-check.svg");
    std::fs::write(&copy_file, &copy).unwrap();
    let out = root.join("copy-check.taxel");
    assert!(taxel(&["build", copy_file.to_str().unwrap(), "-o", out.to_str().unwrap()]).status.success());
    assert!(std::fs::read(&out).unwrap() == after);
    // Saved beside the original as a new file; again only when asked.
    assert_eq!(s.post(&format!("{base2}save"), b"").status, 200);
    assert_eq!(std::fs::read_to_string(root.join("tala-map.tactile.svg")).unwrap(), copy);
    assert_eq!(s.post(&format!("{base2}save"), b"").status, 409);
    assert_eq!(s.post(&format!("{base2}save?overwrite=1"), b"").status, 200);
    assert_eq!(std::fs::read(root.join("tala-map.svg")).unwrap(), original, "the original is untouched");
    // A style the compiler refuses is its diagnostic.
    let bad = s.post(&format!("{base}restyle?element=path1&style=grating(wavelength%3A%20banana)"), b"").json();
    assert!(bad["errors"].as_u64().unwrap() >= 1, "{bad}");
    assert_eq!(s.post(&format!("{base}restyle?element=nope&style=dots()"), b"").status, 400);
}

#[test]
fn a_fill_colour_s_style_is_a_style_sheet_rule_and_builds_as_taxel_build_with_that_sheet() {
    let (_dir, root) = folder();
    let original = std::fs::read(root.join("tala-map.svg")).unwrap();
    let s = Studio::start(&root);
    let v = s.post("/api/open?path=tala-map.svg", b"").json();
    let base = v["base"].as_str().unwrap().to_string();
    assert_eq!(s.get(&format!("{base}sheet.toml")).status, 404, "no sheet before a colour is changed");
    // The drawing's colours, most used first, as #rrggbb.
    let fills = s.get(&format!("{base}fills")).json();
    let fills = fills.as_array().unwrap();
    assert!(fills.len() >= 3, "{fills:?}");
    assert!(fills.windows(2).all(|w| w[0]["count"].as_u64() >= w[1]["count"].as_u64()));
    let fill = fills[0]["fill"].as_str().unwrap().to_string();
    assert!(fill.len() == 7 && fill.starts_with('#'), "{fill}");
    let r = s.post(&format!("{base}restyle?fill={}&style=dots()", fill.replace('#', "%23")), b"");
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let v2 = r.json();
    assert_eq!(v2["sheet"], "tala-map.tactile.toml");
    assert_eq!(v2["changed"], false, "the drawing itself is not changed");
    let base2 = v2["base"].as_str().unwrap().to_string();
    let sheet = String::from_utf8(s.get(&format!("{base2}sheet.toml")).body).unwrap();
    assert!(sheet.ends_with(&format!("[[rule]]\nfill = \"{fill}\"\ntactile = \"dots()\"\n")), "{sheet}");
    // The bundle is `taxel build --style` of that sheet.
    let sheet_file = root.join("check.toml");
    std::fs::write(&sheet_file, &sheet).unwrap();
    let out = root.join("check.taxel");
    let built = taxel(&["build", MAP, "--style", sheet_file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(built.status.success(), "{}", String::from_utf8_lossy(&built.stderr));
    assert!(std::fs::read(&out).unwrap() == s.get(&format!("{base2}bundle")).body);
    // The same colour again: its rule takes the new style, in its place.
    let v3 = s.post(&format!("{base2}restyle?fill={}&style=none", fill.replace('#', "%23")), b"").json();
    let sheet3 = String::from_utf8(s.get(&format!("{}sheet.toml", v3["base"].as_str().unwrap())).body).unwrap();
    assert_eq!(sheet3.matches("[[rule]]").count(), sheet.matches("[[rule]]").count());
    assert!(sheet3.ends_with("tactile = \"none\"\n"), "{sheet3}");
    // Saved beside the original as NAME.tactile.toml, again only when asked.
    assert_eq!(s.post(&format!("{base2}save?what=sheet"), b"").status, 200);
    assert_eq!(std::fs::read_to_string(root.join("tala-map.tactile.toml")).unwrap(), sheet);
    assert_eq!(s.post(&format!("{base2}save?what=sheet"), b"").status, 409);
    assert_eq!(std::fs::read(root.join("tala-map.svg")).unwrap(), original, "the original is untouched");
    // Not a colour, or a style the sheet reader refuses: said, nothing built.
    assert_eq!(s.post(&format!("{base}restyle?fill=red&style=dots()"), b"").status, 400);
    let bad = s.post(&format!("{base}restyle?fill=%23ff0000&style=dots(%22"), b"");
    assert_eq!(bad.status, 400, "{}", String::from_utf8_lossy(&bad.body));
    assert_eq!(s.post(&format!("{base}restyle?fill=%23ff0000&element=path1&style=dots()"), b"").status, 400);
}

#[test]
fn a_profile_file_from_the_page_is_read_as_the_cli_reads_one_and_named_only_by_its_key() {
    let (_dir, root) = folder();
    let s = Studio::start(&root);
    let stress2 = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/format-spec/profiles/stress2.toml"))
        .unwrap()
        .replace("name = \"stress2\"", "name = \"wide\"")
        .replace("width_mm = 110", "width_mm = 150");
    // A broken file: the command line's message, with the file's name.
    let broken = stress2.replace("[array]", "[arrray]");
    let file = root.join("broken.toml");
    std::fs::write(&file, &broken).unwrap();
    let cli = taxel(&["build", MAP, "--profile", file.to_str().unwrap(), "-o", root.join("x.taxel").to_str().unwrap()]);
    let cli = String::from_utf8_lossy(&cli.stderr).into_owned();
    let why = cli.split(file.to_str().unwrap()).nth(1).unwrap_or_else(|| panic!("{cli}")).trim().to_string();
    let r = s.post("/api/profile?name=broken.toml", broken.as_bytes());
    assert_eq!(r.status, 400);
    let said = r.json()["error"].as_str().unwrap().to_string();
    assert_eq!(said, format!("broken.toml{why}"));
    // A good one: its key builds as `taxel build --profile FILE`.
    let r = s.post("/api/profile?name=wide.toml", stress2.as_bytes()).json();
    assert_eq!(r["name"], "wide");
    let key = r["key"].as_str().unwrap();
    let v = s.post(&format!("/api/open?path=tala-map.svg&profile={key}"), b"").json();
    assert_eq!(v["bundle"]["profile"], "wide");
    let bundle = s.get(&format!("{}bundle", v["base"].as_str().unwrap())).body;
    let good = root.join("wide.toml");
    std::fs::write(&good, &stress2).unwrap();
    let out = root.join("wide.taxel");
    assert!(taxel(&["build", MAP, "--profile", good.to_str().unwrap(), "-o", out.to_str().unwrap()]).status.success());
    assert!(std::fs::read(&out).unwrap() == bundle, "the bundle is taxel build --profile FILE's");
    // Only a key names a kept file: never a path.
    for bad in
        ["profile-..%2F..%2Fetc%2Fpasswd", "%2Fetc%2Fpasswd", "profile-0123", "sheet-0123456789abcdef0123456789abcdef"]
    {
        let r = s.post(&format!("/api/open?path=tala-map.svg&profile={bad}"), b"");
        assert_eq!(r.status, 400, "{bad}");
    }
}

#[test]
fn one_element_restyled_in_a_drawing_the_automatic_sheet_styled_keeps_the_others_textures() {
    // Regression: one `data-tactile` made the drawing annotated, so the
    // automatic sheet no longer styled it and every other element lost its
    // texture. The copy is now built with the automatic sheet as decided for
    // the drawing, which the page offers beside the copy.
    let dir = tempfile::tempdir().unwrap();
    let plain = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-plain.svg");
    std::fs::copy(plain, dir.path().join("plain.svg")).unwrap();
    let s = Studio::start(dir.path());
    let v = s.post("/api/open?path=plain.svg", b"").json();
    let base = v["base"].as_str().unwrap().to_string();
    let r = s.post(&format!("{base}restyle?element=oak&style=dots()"), b"");
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let v2 = r.json();
    assert_eq!((v2["changed"].as_bool(), v2["sheet_from_auto"].as_bool()), (Some(true), Some(true)), "{v2}");
    let base2 = v2["base"].as_str().unwrap().to_string();
    let sheet = s.get(&format!("{base2}sheet.toml")).body;
    let decided = taxel(&["style", "auto", plain]);
    assert!(decided.status.success());
    assert_eq!(sheet, decided.stdout, "the sheet is taxel style auto's for the drawing");
    let (copy, sheet_file, out) =
        (dir.path().join("copy.svg"), dir.path().join("copy.toml"), dir.path().join("copy.taxel"));
    std::fs::write(&copy, s.get(&format!("{base2}copy.svg")).body).unwrap();
    std::fs::write(&sheet_file, &sheet).unwrap();
    let built =
        taxel(&["build", copy.to_str().unwrap(), "--style", sheet_file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(built.status.success(), "{}", String::from_utf8_lossy(&built.stderr));
    assert!(std::fs::read(&out).unwrap() == s.get(&format!("{base2}bundle")).body);
    // The other regions are still textured: the summary still counts gratings.
    let styles = v2["styles"].as_str().unwrap_or_default();
    assert!(styles.contains("grating"), "{styles}");
}
