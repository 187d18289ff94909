//! One module per command family; `io` holds what they share (reading inputs, writing outputs).

pub mod cone;
pub mod contact;
pub mod demo;
pub mod io;
pub mod motion;
pub mod plot;
pub mod retime;
pub mod retime_joints;
pub mod robot;
pub mod setup;
pub mod simulate;
pub mod topp;
pub mod view;
