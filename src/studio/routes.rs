//! What each URL does. Every request is checked first (its Host and
//! Origin); every response carries [`security::HEADERS`]. A handler never
//! brings the server down: a bad file is a diagnostic in the page, a
//! compiler panic a 500 for that request alone.
//!
//! | method and path | answer |
//! | --- | --- |
//! | `GET /`, `/studio.js`, `/studio.css`, `/player.js`, `/taxel.wasm` | the page (embedded) |
//! | `GET /api/start` | the opened folder's inputs and bundles, the profiles, the input limit |
//! | `POST /api/build?name=N&profile=P&fit=1` | builds the uploaded body (at most the CLI's input limit) |
//! | `POST /api/open?path=REL&profile=P&fit=1` | builds a file of the opened folder |
//! | `GET /api/r/ID/bundle`, `/key`, `/preview.png`, `/drawing.png`, `/export/FORMAT` | a build's parts (`key`: the key's own bundle; `key2`, `key3` ...: its further pages) |
//! | `GET /api/r/ID/outlines?ids=A,B` | the footprints of elements, for highlighting |
//! | `POST /api/profile?name=FILE` | a profile file (the body) checked and kept; its key for `profile=` |
//! | `POST /api/r/ID/restyle?element=ID&style=S` | the drawing rebuilt with that element's style (in a copy) |
//! | `POST /api/r/ID/restyle?fill=%23RRGGBB&style=S` | rebuilt with every element of that fill styled (a style sheet) |
//! | `GET /api/r/ID/fills` | the drawing's fill colours, most used first |
//! | `GET /api/r/ID/copy.svg`, `/sheet.toml` | the restyled copy, the teacher's style sheet (downloads) |
//! | `POST /api/r/ID/save?what=svg\|sheet&overwrite=0\|1` | the copy or the sheet saved beside the original |

use std::io::Read;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use percent_encoding::percent_decode_str;
use serde_json::json;
use tiny_http::{Header, Method, Request, Response};

use super::{Studio, assets, security, work};
use crate::cli::{CompileOpts, ExportFormat};
use crate::io::read::MAX_INPUT_BYTES;

type Reply = Response<std::io::Cursor<Vec<u8>>>;

/// Answers one request.
pub fn answer(studio: &Studio, mut request: Request) {
    let reply = match catch_unwind(AssertUnwindSafe(|| handle(studio, &mut request))) {
        Ok(r) => r,
        Err(_) => error(500, "internal error: the compiler panicked on this input; please report it"),
    };
    let mut reply = reply;
    for (k, v) in security::HEADERS {
        reply.add_header(header(k, v));
    }
    // The client may have gone; nothing to do about it.
    let _ = request.respond(reply);
}

fn handle(studio: &Studio, request: &mut Request) -> Reply {
    let head = |name: &str| {
        request
            .headers()
            .iter()
            .find(|h| h.field.as_str().as_str().eq_ignore_ascii_case(name))
            .map(|h| h.value.as_str().to_string())
    };
    if let Some(why) = studio.hosts.refusal(head("Host").as_deref(), head("Origin").as_deref()) {
        return error(403, why);
    }
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let param = |key: &str| query_param(query, key);
    let method = request.method().clone();
    match (&method, path) {
        (Method::Get | Method::Head, p) if let Some(a) = assets::find(p) => {
            Response::from_data(a.bytes.to_vec()).with_header(header("Content-Type", a.mime))
        }
        (Method::Get, "/api/start") => start(studio),
        (Method::Post, "/api/build") => {
            let body = match read_body(request) {
                Ok(b) => b,
                Err(r) => return r,
            };
            let name = param("name").unwrap_or_default();
            let name = Path::new(&name).file_name().and_then(|n| n.to_str()).unwrap_or("upload").to_string();
            // An upload is compiled as a file in an empty folder: a glTF's
            // buffers are read only beside it, and there is nothing there.
            let Ok(dir) = tempfile::tempdir() else { return error(500, "cannot make a temporary folder") };
            let fit = param("fit").as_deref() == Some("1");
            build_reply(studio, &name, &dir.path().join(&name), body, (param("profile"), fit), Carry::default())
        }
        (Method::Post, "/api/profile") => {
            let body = match read_body(request) {
                Ok(b) => b,
                Err(r) => return r,
            };
            let name = param("name").unwrap_or_default();
            let name = Path::new(&name).file_name().and_then(|n| n.to_str()).unwrap_or("profile.toml").to_string();
            profile_upload(studio, &name, &body)
        }
        (Method::Post, "/api/open") => {
            let rel = param("path").unwrap_or_default();
            let file = match security::inside(&studio.root, &rel) {
                Ok(f) if f.is_file() => f,
                Ok(_) => return error(404, &format!("'{rel}' is not a file")),
                Err(why) => return error(403, &why),
            };
            match crate::io::read_input(&file) {
                Ok(bytes) => {
                    let fit = param("fit").as_deref() == Some("1");
                    let carry = Carry { opened: Some(file.clone()), ..Carry::default() };
                    build_reply(studio, &rel, &file, bytes, (param("profile"), fit), carry)
                }
                Err(e) => error(400, &format!("{e:#}")),
            }
        }
        (m, p) if let Some(rest) = p.strip_prefix("/api/r/") => {
            let (id, part) = rest.split_once('/').unwrap_or((rest, ""));
            let Some(built) = id.parse().ok().and_then(|id| studio.kept(id)) else {
                return error(404, "this build is no longer kept; open the file again");
            };
            part_reply(studio, &built, m, part, &param, request)
        }
        (Method::Get | Method::Post, _) => error(404, "no such page"),
        _ => error(405, "method not allowed"),
    }
}

/// The parts of a kept build.
fn part_reply(
    studio: &Studio,
    built: &work::Built,
    method: &Method,
    part: &str,
    param: &dyn Fn(&str) -> Option<String>,
    request: &mut Request,
) -> Reply {
    let stem = Path::new(&built.name).file_stem().and_then(|s| s.to_str()).unwrap_or("drawing");
    match (method, part) {
        (Method::Get, "bundle") => match &built.bundle_bytes {
            Some(b) => download(b.clone(), &format!("{stem}.taxel"), "application/octet-stream"),
            None => error(404, "no bundle: the input has errors"),
        },
        // The key's pages: `key`, then `key2`, `key3` ..., named as `taxel build` writes them.
        (Method::Get, p) if let Some(page) = key_page(p) => match built.key_bytes.get(page - 1) {
            Some(b) => {
                let name = crate::batch::output::key_page_path(Path::new(&format!("{stem}.taxel")), page);
                download(b.clone(), &name.display().to_string(), "application/octet-stream")
            }
            None if built.key_bytes.is_empty() => {
                error(404, "no key bundle: the drawing needs no key, or its profile shows the key itself")
            }
            None => error(404, &format!("no such page: the key has {} pages", built.key_bytes.len())),
        },
        (Method::Get, "preview.png") => png(built.preview_png.as_ref()),
        (Method::Get, "drawing.png") => png(built.drawing_png.as_ref()),
        (Method::Get, p) if let Some(f) = p.strip_prefix("export/") => {
            let format = match f {
                "dtms" => ExportFormat::Dtms,
                "graphiti" => ExportFormat::Graphiti,
                "unicode" => ExportFormat::Unicode,
                _ => return error(404, "no such export: dtms, graphiti or unicode"),
            };
            match work::export(built, format) {
                Ok((file, data)) => download(data, &file, "application/octet-stream"),
                Err(e) => error(400, &format!("{e:#}")),
            }
        }
        (Method::Get, "outlines") => {
            let ids = param("ids").unwrap_or_default();
            let ids: Vec<&str> = ids.split(',').filter(|s| !s.is_empty()).collect();
            json_reply(200, &work::outlines(built, &ids))
        }
        (Method::Post, "restyle") => {
            // The request carries nothing but its query; its body, if any, is not read.
            let _ = request;
            restyle(studio, built, param("element"), param("fill"), param("style"))
        }
        (Method::Get, "fills") => json_reply(200, &work::fills(built)),
        (Method::Get, "sheet.toml") => match &built.sheet {
            Some(s) => download(s.text().into_bytes(), &work::sheet_name(built), "application/toml"),
            None => error(404, "no style sheet: no colour's style was changed"),
        },
        (Method::Get, "copy.svg") => match &built.svg_text {
            Some(t) => download(t.clone().into_bytes(), &format!("{stem}.tactile.svg"), "image/svg+xml"),
            None => error(404, "only a drawing has a copy"),
        },
        (Method::Post, "save") => {
            let sheet = param("what").as_deref() == Some("sheet");
            save(studio, built, sheet, param("overwrite").as_deref() == Some("1"))
        }
        _ => error(404, "no such part"),
    }
}

/// `GET /api/start`: what the page shows first.
fn start(studio: &Studio) -> Reply {
    let mut files = Vec::new();
    if let Ok(found) = crate::batch::discover::discover_all(std::slice::from_ref(&studio.root)) {
        files.extend(found.inputs.iter().map(|i| i.key()));
    }
    // Bundles of the folder (at its top level and one below).
    for e in walkdir::WalkDir::new(&studio.root).max_depth(2).into_iter().flatten() {
        if e.file_type().is_file()
            && e.path().extension().is_some_and(|x| x == "taxel")
            && let Ok(rel) = e.path().strip_prefix(&studio.root)
        {
            files.push(rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
        }
    }
    files.sort();
    json_reply(
        200,
        &json!({
            "root": studio.root.display().to_string(),
            "file": studio.file,
            "files": files,
            "profiles": taxel_format::profiles::builtin_names(),
            "default_profile": studio.opts.profile,
            "max_input_bytes": MAX_INPUT_BYTES,
        }),
    )
}

/// Builds and answers with the summary (and the build's id and URLs).
fn build_reply(
    studio: &Studio,
    name: &str,
    path: &Path,
    bytes: Vec<u8>,
    (profile, fit): (Option<String>, bool),
    carry: Carry,
) -> Reply {
    let mut opts = studio.opts.clone();
    // The page's "fit" adds `--fit`; it never takes away the command line's.
    opts.fit |= fit;
    if let Some(p) = profile.filter(|p| !p.is_empty()) {
        // A built-in profile by name, or a profile file the page uploaded
        // (`POST /api/profile`) by its key: the page cannot name a path.
        if let Some(file) = studio.stashed("profile", &p) {
            opts.profile = Some(file.display().to_string());
        } else if taxel_format::profiles::builtin(&p).is_some() {
            opts.profile = Some(p);
        } else {
            return error(400, &format!("'{p}' is not a built-in profile nor a profile file opened in this studio"));
        }
    }
    build_with(studio, name, path, bytes, opts, carry).unwrap_or_else(|e| error(500, &format!("{e:#}")))
}

/// What a build carries over from the one it changes.
#[derive(Default)]
struct Carry {
    /// Where the drawing was opened from in the folder.
    opened: Option<std::path::PathBuf>,
    /// The teacher's style sheet.
    sheet: Option<work::Sheet>,
    /// Whether the drawing is a changed copy.
    changed: bool,
    /// Whether the automatic sheet styled the original drawing.
    auto_styled: bool,
    /// The drawing's picture and fill colours, when a style change kept
    /// them (the drawing looks as before).
    looks: Option<(work::Looks, std::sync::OnceLock<serde_json::Value>)>,
}

fn build_with(
    studio: &Studio,
    name: &str,
    path: &Path,
    bytes: Vec<u8>,
    opts: CompileOpts,
    carry: Carry,
) -> anyhow::Result<Reply> {
    let (looks, fills) = carry.looks.unzip();
    let mut built = work::build(name, path, bytes, &opts, looks)?;
    if let Some(fills) = fills {
        built.fills = fills;
    }
    built.opened = carry.opened;
    built.sheet = carry.sheet;
    built.changed = carry.changed;
    built.auto_styled |= carry.auto_styled;
    let (id, built) = studio.keep(built);
    let mut summary = built.summary.clone();
    if let serde_json::Value::Object(s) = &mut summary {
        s.insert("id".into(), json!(id));
        s.insert("base".into(), json!(format!("/api/r/{id}/")));
        s.insert("has_preview".into(), json!(built.preview_png.is_some()));
        s.insert("has_drawing".into(), json!(built.drawing_png.is_some()));
        s.insert("can_save".into(), json!(built.opened.is_some() && built.svg_text.is_some()));
        s.insert("changed".into(), json!(built.changed));
        s.insert("sheet".into(), json!(built.sheet.as_ref().map(|_| work::sheet_name(&built))));
        s.insert("sheet_from_auto".into(), json!(built.sheet.as_ref().is_some_and(|sh| sh.from_auto)));
    }
    Ok(json_reply(200, &summary))
}

/// `POST /api/r/ID/save`: the drawing's copy beside the original, as
/// `NAME.tactile.svg` (or, `what=sheet`, the teacher's style sheet as
/// `NAME.tactile.toml`); never the original itself, and an existing file
/// only when the page asked (`overwrite=1`, after the teacher confirmed).
fn save(studio: &Studio, built: &work::Built, sheet: bool, overwrite: bool) -> Reply {
    let (Some(original), Some(svg)) = (&built.opened, &built.svg_text) else {
        return error(400, "only a drawing opened from the folder can be saved beside it; download the copy instead");
    };
    let stem = original.file_stem().and_then(|s| s.to_str()).unwrap_or("drawing");
    let stem = stem.strip_suffix(".tactile").unwrap_or(stem);
    let Some(dir) = original.parent() else { return error(400, "the drawing has no folder") };
    let (target, text) = match (sheet, &built.sheet) {
        (true, Some(s)) => (dir.join(format!("{stem}.tactile.toml")), s.text()),
        (true, None) => return error(400, "no style sheet: no colour's style was changed"),
        (false, _) => (dir.join(format!("{stem}.tactile.svg")), svg.clone()),
    };
    if !target.starts_with(&studio.root) || target == *original {
        return error(403, "the copy would not be a new file in the opened folder");
    }
    if target.exists() && !overwrite {
        return error(409, &format!("{} exists; overwrite it?", target.display()));
    }
    match crate::io::write_file(&target, text.as_bytes()) {
        Ok(()) => json_reply(200, &json!({"saved": target.display().to_string()})),
        Err(e) => error(500, &e.to_string()),
    }
}

/// `POST /api/r/ID/restyle`: the drawing rebuilt with one element's style
/// changed (`element`, as `data-tactile` in a copy) or every element of one
/// fill colour's (`fill`, as a rule of the teacher's style sheet). The
/// change builds on the build it changes: its copy, its sheet, its options.
fn restyle(
    studio: &Studio,
    built: &work::Built,
    element: Option<String>,
    fill: Option<String>,
    style: Option<String>,
) -> Reply {
    let Some(style) = style else { return error(400, "restyle needs a style") };
    let Some(svg) = &built.svg_text else { return error(400, "only a drawing's styles can be changed") };
    let mut opts = built.opts.clone();
    let mut carry = Carry {
        opened: built.opened.clone(),
        sheet: built.sheet.clone(),
        changed: built.changed,
        auto_styled: built.auto_styled,
        looks: Some(((built.drawing_png.clone(), built.backdrop.clone()), built.fills.clone())),
    };
    let text = match (element, fill) {
        (Some(element), None) => match work::restyle(built, &element, &style) {
            Ok(text) => {
                carry.changed = true;
                // An annotation turns the automatic sheet off for the whole
                // drawing: where it styled the drawing, the copy is built
                // with it as decided for the drawing, so that one element's
                // change leaves the others' textures as they were.
                if carry.sheet.is_none() && built.auto_styled {
                    carry.sheet = match work::auto_sheet(built) {
                        Ok(sheet) => Some(sheet),
                        Err(why) => return error(400, &why),
                    };
                }
                text
            }
            Err(why) => return error(400, &why),
        },
        (None, Some(fill)) => match work::sheet_with(built, &fill, &style) {
            Ok(sheet) => {
                carry.sheet = Some(sheet);
                svg.clone()
            }
            Err(why) => return error(400, &why),
        },
        _ => return error(400, "restyle needs an element or a fill colour, not both"),
    };
    if let Some(sheet) = &carry.sheet {
        match studio.stash("sheet", &sheet.text()) {
            Ok((_, path)) => opts.style = Some(path),
            Err(e) => return error(500, &format!("{e:#}")),
        }
    }
    let path = Path::new(&built.name);
    build_with(studio, &built.name, path, text.into_bytes(), opts, carry)
        .unwrap_or_else(|e| error(500, &format!("{e:#}")))
}

/// `POST /api/profile`: a profile file from the page, read as `--profile
/// FILE` reads one; kept for builds under its key, or refused with the
/// reader's message.
fn profile_upload(studio: &Studio, name: &str, body: &[u8]) -> Reply {
    let Ok(text) = std::str::from_utf8(body) else {
        return error(400, &format!("{name}: not a profile file: it is not UTF-8 text"));
    };
    // The reader's message names the file and the key at fault, as the command line prints it.
    let profile = match taxel_format::profiles::parse(text, name) {
        Ok(p) => p,
        Err(e) => return error(400, &e.to_string()),
    };
    if profile.family() == taxel_format::Family::Print {
        return error(
            400,
            &format!("{name}: a print profile makes files to print, not a bundle to play: use taxel build"),
        );
    }
    match studio.stash("profile", text) {
        Ok((key, _)) => json_reply(
            200,
            &json!({"key": key, "name": profile.name.as_str(), "family": profile.family().name(), "file": name}),
        ),
        Err(e) => error(500, &format!("{e:#}")),
    }
}

/// The request's body, refused past the CLI's input limit before it is read.
fn read_body(request: &mut Request) -> Result<Vec<u8>, Reply> {
    let too_big = || {
        error(413, &format!("the file is larger than the {} MB input limit; split the drawing", MAX_INPUT_BYTES >> 20))
    };
    if request.body_length().is_some_and(|n| n as u64 > MAX_INPUT_BYTES) {
        return Err(too_big());
    }
    let mut body = Vec::new();
    if request.as_reader().take(MAX_INPUT_BYTES + 1).read_to_end(&mut body).is_err() {
        return Err(error(400, "the upload could not be read"));
    }
    if body.len() as u64 > MAX_INPUT_BYTES {
        return Err(too_big());
    }
    Ok(body)
}

/// The value of `key` in a query string, percent-decoded.
/// The page of the key a part names: `key` is the first, `key2` the second ...
fn key_page(part: &str) -> Option<usize> {
    match part.strip_prefix("key")? {
        "" => Some(1),
        n if n.bytes().all(|b| b.is_ascii_digit()) && !n.starts_with('0') => n.parse().ok().filter(|&k| k >= 2),
        _ => None,
    }
}

fn query_param(query: &str, key: &str) -> Option<String> {
    query.split('&').find_map(|kv| {
        let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
        (k == key).then(|| percent_decode_str(v).decode_utf8().ok().map(|s| s.into_owned())).flatten()
    })
}

fn header(k: &str, v: &str) -> Header {
    // Every header is a constant or built from sanitised names, so it is valid.
    Header::from_bytes(k.as_bytes(), v.as_bytes())
        .unwrap_or_else(|_| Header::from_bytes(&b"X-Invalid"[..], &b"1"[..]).expect("a constant header is valid"))
}

fn json_reply(status: u16, v: &serde_json::Value) -> Reply {
    Response::from_data(v.to_string().into_bytes())
        .with_status_code(status)
        .with_header(header("Content-Type", "application/json"))
}

fn error(status: u16, message: &str) -> Reply {
    json_reply(status, &json!({ "error": message }))
}

fn png(data: Option<&Vec<u8>>) -> Reply {
    match data {
        Some(d) => Response::from_data(d.clone()).with_header(header("Content-Type", "image/png")),
        None => error(404, "no picture: the input has errors"),
    }
}

/// A file to save, never shown in the page (a drawing's copy could hold scripts).
fn download(data: Vec<u8>, file: &str, mime: &str) -> Reply {
    let safe: String =
        file.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '_' }).collect();
    Response::from_data(data)
        .with_header(header("Content-Type", mime))
        .with_header(header("Content-Disposition", &format!("attachment; filename=\"{safe}\"")))
        .with_header(header("Content-Security-Policy", "sandbox"))
}
