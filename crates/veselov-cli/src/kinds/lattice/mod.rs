//! Lattice field scenarios: sine-Gordon, the linear wave equation and φ⁴
//! Klein–Gordon on a 1+1 spacetime lattice, with the schemes of seed 002 §5.
//!
//! ```toml
//! [model]
//! name = "sine-gordon"     # sine-gordon | wave | klein-gordon-phi4
//! params = { m2 = 1.0, lambda = 1.0 }   # klein-gordon-phi4: N = −½m²φ² − ¼λφ⁴
//! [lattice]
//! nodes = 255
//! length = 40.0
//! boundary = "periodic"    # periodic | winding (jump = 2π by default)
//! courant = 0.125          # or: dt = 0.0196…
//! [method]
//! scheme = "triangle"      # triangle | triangle-explicit | rectangle | symmetric-rectangle | vu-quoc-li | guo
//! [initial]
//! kind = "kink-antikink"   # kink-antikink | kink | breather | dalembert
//! [time]
//! t_end = 200.0
//! [output]
//! dir = "out/sg"
//! snapshot_every = 100
//! ```
//!
//! [`schema`] reads and validates the file; [`run`] builds the lattice, the
//! cell rule and the initial levels and marches them, on the fast path (the
//! scheme's own solver, periodic lattices) or the generic one (a cell
//! Lagrangian), with the observer of [`observer`]; [`figures`] draws the
//! energy error, the final waveform and the space–time heat map.

pub mod figures;
pub mod observer;
pub mod run;
pub mod schema;
