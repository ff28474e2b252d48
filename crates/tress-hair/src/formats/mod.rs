//! Hair file formats: Cem Yuksel `.hair` and TressFX `.tfx`.
