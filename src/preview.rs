//! `--preview` (built with `--features preview`): a window that shows each
//! pass of `--watch` as it is written, the coarse one and then the full
//! picture, scaled to the window with its proportions kept. Closing the
//! window ends the program as Ctrl-C does, with status 0.
//!
//! The window lives on a thread of its own, which owns it from creation
//! to the end (X11 through minifb wants one thread per window) and polls
//! its events every few milliseconds; the watch loop hands it pictures
//! through a shared slot and never waits for it.

use crate::render::Film;
use crate::scene::Transfer;
use std::sync::mpsc::sync_channel;
use std::sync::{Arc, Mutex};

/// A picture for the window: 0RGB pixels, row by row.
struct Frame {
    width: usize,
    height: usize,
    pixels: Vec<u32>,
}

/// The preview window, opened with the first picture.
#[derive(Default)]
pub struct Preview {
    /// The next picture to show, taken by the window's thread.
    next: Option<Arc<Mutex<Option<Frame>>>>,
}

impl Preview {
    /// Shows `film` (encoded as the image file is); the first call opens
    /// the window, and fails if there is no display to open it on.
    pub fn show(&mut self, film: &Film, transfer: Transfer, title: &str) -> Result<(), String> {
        let rgb = crate::output::to_rgb8(film, transfer);
        let frame = Frame {
            width: film.width as usize,
            height: film.height as usize,
            pixels: rgb
                .pixels()
                .map(|p| u32::from_be_bytes([0, p[0], p[1], p[2]]))
                .collect(),
        };
        match &self.next {
            Some(slot) => {
                *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(frame);
                Ok(())
            }
            None => {
                self.next = Some(open(frame, title.to_string())?);
                Ok(())
            }
        }
    }
}

/// Starts the window's thread with its first picture; returns once the
/// window exists, or with the reason it could not be made.
fn open(first: Frame, title: String) -> Result<Arc<Mutex<Option<Frame>>>, String> {
    let slot = Arc::new(Mutex::new(None::<Frame>));
    let shared = slot.clone();
    let (ready, opened) = sync_channel::<Result<(), String>>(1);
    std::thread::spawn(move || {
        let options = minifb::WindowOptions {
            resize: true,
            scale_mode: minifb::ScaleMode::AspectRatioStretch,
            ..minifb::WindowOptions::default()
        };
        let mut window = match minifb::Window::new(&title, first.width, first.height, options) {
            Ok(w) => {
                let _ = ready.send(Ok(()));
                w
            }
            Err(e) => {
                let _ = ready.send(Err(e.to_string()));
                return;
            }
        };
        // Redrawn at a modest rate whether or not the picture changed (a
        // window uncovered or resized needs it), leaving the cores to the
        // render.
        window.set_target_fps(20);
        let mut shown = first;
        while window.is_open() {
            if let Some(f) = shared.lock().unwrap_or_else(|e| e.into_inner()).take() {
                shown = f;
            }
            if window
                .update_with_buffer(&shown.pixels, shown.width, shown.height)
                .is_err()
            {
                break;
            }
        }
        // Closed by the user: end as an interrupted watch ends, but with
        // success, since closing the window is how one stops it.
        crate::output::remove_pending();
        std::process::exit(0);
    });
    match opened.recv() {
        Ok(Ok(())) => Ok(slot),
        Ok(Err(e)) => Err(e),
        Err(_) => Err("the window's thread ended".to_string()),
    }
}
