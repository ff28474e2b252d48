//! One module per subcommand.

pub(crate) mod animate;
pub(crate) mod bake_ao;
pub(crate) mod bench;
pub(crate) mod cards;
pub(crate) mod compare;
pub(crate) mod compare_images;
pub(crate) mod convert;
pub(crate) mod exact_oit;
pub(crate) mod generate;
pub(crate) mod info;
pub(crate) mod open;
pub(crate) mod reference;
pub(crate) mod render;
pub(crate) mod render_satf;
pub(crate) mod report;
pub(crate) mod satf_bake;
pub(crate) mod settings;
pub(crate) mod simulate;
pub(crate) mod view;
