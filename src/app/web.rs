//! The browser build's side of the window: the same [`App`](super) on winit's web backend,
//! started from the page (crates/volley-web), with the page's URL as its command line.
//!
//! - `?scene=NAME` opens a bundled scene (`seed` without one), `?scene=URL.ron` a scene or
//!   saved setup fetched from that URL; `?integrator=NAME` picks the
//!   integrator as `--integrator` does; `?backend=webgl` keeps to WebGL2 even where the
//!   browser has WebGPU (`webgpu` the other way; both, WebGPU first, without it). A name that is not one shows the CLI's one-line error in
//!   the page (`#volley-error`) instead of the window.
//! - `?replay=URL` fetches a recording (one `volley record` wrote, served beside the page or
//!   from any URL the page may fetch) and replays it, verifying every stored hash and keyframe.
//! - The canvas carries what a test or a curious user can read without a debugger:
//!   `data-frames` (frames drawn), `data-tick` (the first lane's tick), `data-scene`,
//!   `data-adapter`, `data-lanes` (the lanes' integrators, comma-separated), `data-aims` (how
//!   many lanes fired their last aim) and, while replaying, `data-replay` (the verdict line).
//!
//! What a page does differently (downloads for files, no hot reload, the GPU's answers arriving
//! later, errors in the page) is [`crate::platform`]'s, which the window calls everywhere else;
//! this module is only the page's start. What a page cannot do is said in the panel where it
//! matters: there is no file to watch for hot reload, and recordings, screenshots and PNG plots
//! are not written (no file system).
//! The simulation runs on the page's one thread: rayon, finding no threads, runs every chunk
//! on it, which gives the same bits as any other thread count (docs/physics.md, "Determinism").

use std::path::PathBuf;

use wasm_bindgen::JsCast;
use winit::event_loop::EventLoop;
use winit::platform::web::EventLoopExtWebSys;

use super::session::replaying::ReplaySource;
use super::{App, Session, WindowOptions};
use crate::platform::web::{listen_to_file_input, param, show_error};

pub use crate::platform::web::ERROR_ID;

/// Opens the window in the page on the scene the URL names, or shows why not.
pub fn start() {
    std::panic::set_hook(Box::new(|info| {
        show_error(&format!("the page's Volley stopped: {info}"));
    }));
    listen_to_file_input();
    if let Err(message) = open() {
        show_error(&message);
    }
}

fn open() -> Result<(), String> {
    if let Some(url) = param("replay") {
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(message) = open_replay(&url).await {
                show_error(&message);
            }
        });
        return Ok(());
    }
    let name = param("scene").unwrap_or_else(|| "seed".into());
    let bundled = crate::scene::BUNDLED.iter().any(|(n, _)| *n == name);
    if !bundled && name.ends_with(".ron") {
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(message) = open_scene_url(&name).await {
                show_error(&message);
            }
        });
        return Ok(());
    }
    // A page has no files: a name that is not bundled gets the CLI's line for it.
    if !bundled {
        return Err(format!("error: {}", crate::no_such_scene(&name)));
    }
    let mut scene = crate::scene::bundled(&name).map_err(|e| format!("error: {e}"))?;
    if let Some(integrator) = param("integrator") {
        // The CLI's words for `--integrator` (src/cli/args.rs, parse_integrator).
        let parsed = crate::Integrator::parse(&integrator).ok_or_else(|| {
            let names: Vec<_> = crate::Integrator::ALL.iter().map(|i| i.name()).collect();
            format!(
                "error: ?integrator: unknown `{integrator}`, expected one of {}",
                names.join(", ")
            )
        })?;
        scene
            .set_integrator(parsed)
            .map_err(|e| format!("error: ?integrator={integrator}: {e}"))?;
    }
    let path = PathBuf::from(format!("assets/scenes/{name}.ron"));
    let compare = scene.compare().to_vec();
    let session = Session::with_lanes(scene, &path, compare.clone(), false);
    run(session, compare)
}

/// `?scene=URL.ron`: fetches a scene or saved setup and opens it, checked as `volley window
/// FILE` checks it (errors name the URL, line and column).
async fn open_scene_url(url: &str) -> Result<(), String> {
    let bytes = fetch(url).await.map_err(|e| format!("error: {url}: {e}"))?;
    let text = String::from_utf8(bytes).map_err(|_| format!("error: {url}: not UTF-8 text"))?;
    let stem = url
        .rsplit('/')
        .next()
        .unwrap_or(url)
        .trim_end_matches(".ron")
        .to_string();
    let scene = crate::scene::parse(&text, url, &stem).map_err(|e| format!("error: {e}"))?;
    let compare = scene.compare().to_vec();
    let session = Session::with_lanes(scene, &PathBuf::from(url), compare.clone(), false);
    run(session, compare)
}

/// `?replay=URL`: fetches the recording and replays it, verifying every stored hash and
/// keyframe as it goes; the verdict is the panel's and the canvas's `data-replay`.
async fn open_replay(url: &str) -> Result<(), String> {
    let bytes = fetch(url).await.map_err(|e| format!("error: {url}: {e}"))?;
    let source = ReplaySource::Bytes {
        name: PathBuf::from(url),
        bytes: bytes.into(),
    };
    let session = Session::for_replay_from(source, None).map_err(|e| format!("error: {e}"))?;
    run(session, Vec::new())
}

/// The bytes at `url`, or why not (the HTTP status, or the browser's reason).
async fn fetch(url: &str) -> Result<Vec<u8>, String> {
    use wasm_bindgen_futures::JsFuture;
    let reason = |e: wasm_bindgen::JsValue| {
        e.as_string()
            .or_else(|| js_sys::Error::from(e).message().as_string())
            .unwrap_or_else(|| "the request failed".into())
    };
    let window = web_sys::window().ok_or("no window")?;
    let response: web_sys::Response = JsFuture::from(window.fetch_with_str(url))
        .await
        .map_err(reason)?
        .dyn_into()
        .map_err(|_| "not an HTTP response".to_string())?;
    if !response.ok() {
        return Err(format!(
            "HTTP {} {}",
            response.status(),
            response.status_text()
        ));
    }
    let buffer = JsFuture::from(response.array_buffer().map_err(reason)?)
        .await
        .map_err(reason)?;
    Ok(js_sys::Uint8Array::new(&buffer).to_vec())
}

/// Opens the window on `session`.
fn run(session: Session, compare: Vec<crate::scene::CompareLane>) -> Result<(), String> {
    let options = WindowOptions {
        compare,
        equal_cost: false,
        exit_after_frames: None,
        screenshot: None,
        size: page_size(),
        frame_rate: None,
        paused: false,
        time_scale: 1.0,
        // Asked for so the panel says why a page has no hot reload.
        watch: true,
        scenes: crate::scene::BUNDLED
            .iter()
            .filter(|(n, _)| !n.starts_with("bench/"))
            .map(|(n, _)| {
                (
                    n.to_string(),
                    PathBuf::from(format!("assets/scenes/{n}.ron")),
                )
            })
            .collect(),
        record: None,
        surface_drill: false,
        script: Vec::new(),
        history_budget: crate::timeline::DEFAULT_BUDGET,
        warm_up_ticks: 0,
        display: None,
        policy: crate::pacing::DEFAULT_POLICY.with_refresh(super::display::DEFAULT_REFRESH),
        draw: crate::pacing::DEFAULT_DRAW,
    };
    let event_loop = EventLoop::new().map_err(|e| format!("error: no event loop: {e}"))?;
    event_loop.spawn_app(App::new(session, options));
    Ok(())
}

/// The page's inner size (CSS px), the window's first size.
fn page_size() -> (u32, u32) {
    let size = web_sys::window().and_then(|w| {
        let width = w.inner_width().ok()?.as_f64()?;
        let height = w.inner_height().ok()?.as_f64()?;
        Some((width as u32, height as u32))
    });
    size.filter(|&(w, h)| w >= 320 && h >= 240)
        .unwrap_or((1280, 800))
}
