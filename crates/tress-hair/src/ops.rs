//! Operations on hair assets: transform, resample, subset.
