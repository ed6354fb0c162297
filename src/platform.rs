//! The one seam between the desktop build and the browser build (crates/volley-web, on winit's
//! web backend): what a page does differently, behind a few constants and functions with a
//! desktop implementation (`platform/native.rs`) and a browser one (`platform/web.rs`), so the
//! window, the session, the renderer and the plots call them without `cfg` lines. The list
//! below is the contract: each build compiles its own side, and a name one side lacks fails
//! that build.
//!
//! | what | desktop | browser |
//! |---|---|---|
//! | the clock ([`Instant`], [`SystemTime`]) | std's | the page's `performance.now()` (web-time) |
//! | recordings, saved setups ([`WRITES_FILES`], [`save_file`], [`offer_download`]) | files | downloads |
//! | screenshots ([`save_screenshot`]) | the frame read back, a PNG file | the canvas's image, a download |
//! | a scene by path ([`load_scene`]) | the file | the bundled scene of that name |
//! | files opened ([`take_picked`]) | the command line's | the page's file input |
//! | hot reload ([`FolderWatch`]) | the folder watched | refused: a page cannot watch files |
//! | the GPU's futures ([`CAN_BLOCK`], [`block_on`], [`complete`]) | blocked on | spawned; the answer comes later |
//! | the GPU ([`gpu_instance`], [`report_gpu_errors`], [`IN_BROWSER`]) | wgpu's backends and its default error handler | `?backend=`, WebGPU or WebGL2, errors shown in the page |
//! | the window ([`on_page`]) | a window | a canvas added to the page |
//! | what went wrong, and the run's facts ([`show_error`], [`show_on_page`]) | the command line prints them | the page's `#volley-error`, the canvas's `data-*` |
//! | PNG plots ([`register_plot_font`]) | the embedded font | refused: no font rasteriser |
//! | the allocator ([`keep_freed_heap`]) | glibc's tuned | nothing to tune |

pub use web_time::{Instant, SystemTime, UNIX_EPOCH};

#[cfg(not(target_arch = "wasm32"))]
mod native;
#[cfg(not(target_arch = "wasm32"))]
use native as imp;
#[cfg(target_arch = "wasm32")]
pub mod web;
#[cfg(target_arch = "wasm32")]
use web as imp;

pub use imp::{
    CAN_BLOCK, FolderWatch, IN_BROWSER, WRITES_FILES, block_on, complete, gpu_instance,
    keep_freed_heap, load_scene, offer_download, on_page, register_plot_font, report_gpu_errors,
    save_file, save_screenshot, show_error, show_on_page, take_picked,
};
