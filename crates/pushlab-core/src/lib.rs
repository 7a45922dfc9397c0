//! pushlab-core: predicting and learning how a pushed object moves.
//!
//! This crate implements the combined prediction model of Gao, Ouyang and Tomizuka, "Online Learning
//! in Planar Pushing with Combined Prediction Model": a small MLP predicts the contact point and the
//! contact motion, Lynch's quasi-static model turns them into the object's motion, and a COM
//! correction accounts for an off-centre centre of mass. The few physical parameters
//! `θ_online = (COM offset, h)` are learned online, step by step.
//!
//! It knows nothing of any user interface: the app, the CLI and the tests all drive it the same way.
//!
//! Conventions, once for the whole crate:
//! - SI units everywhere: metres, radians, seconds.
//! - The **COM offset** is `COM − geometric centre`, in the object frame. The paper's `v` is its
//!   negative (`v = centre − COM`); this crate never exposes `v`.
//! - Frames are named in identifiers: `robot_in_object`, `world_from_object`.
//! - `sin`, `atan2`, `exp` and their kin come from [`math`], the same bits on every target; tests
//!   may check against the platform's.

#![cfg_attr(test, allow(clippy::disallowed_methods))]

pub mod atomic_file;
pub mod control;
pub mod domain;
pub mod experiment;
pub mod files;
pub mod geometry;
pub mod inspect;
pub mod json_problem;
pub mod labels;
pub mod learn;
pub mod live;
pub mod math;
pub mod model;
pub mod model_file;
mod parallel;
pub mod pattern;
mod real;
pub mod recording;
pub mod rng;
pub mod sandbox;
pub mod sim;
mod simd;
pub mod slices;
pub mod trajectory;
