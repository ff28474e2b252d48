//! Procedural hair: a head and hair styles grown from its scalp.
