//! CPU reference ("twin") of every shading and shadowing formula used by the tress shaders.
