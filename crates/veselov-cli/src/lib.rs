//! The `veselov` command as a library: scenario files, the built-in catalogue,
//! the kinds of scenario with their run and verify jobs (one folder each under
//! [`kinds`], dispatched by [`route`]), the run pipeline they share, output
//! writers and plots. The binary in `main.rs` only parses the command line.

pub mod animation;
pub mod catalog;
pub mod centerline;
pub mod error;
pub mod figures;
pub mod gif_frames;
pub mod heatmap;
pub mod keys;
pub mod kinds;
pub mod output;
pub mod pipeline;
pub mod plot;
pub mod progress;
pub mod redraw;
pub mod route;
pub mod scenario;
#[cfg(test)]
mod test_scratch;
pub mod verdict;
pub mod verify;
