//! Ambient-occlusion bake speed for the default generated patch head. Run with
//! `cargo bench -p tress-hair --bench ao`.

fn main() {
    divan::main();
}
