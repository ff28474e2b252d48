//! The wgpu renderer of tress.
