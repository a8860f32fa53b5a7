//! The shipped standard NC code (`standard/*.tpl`), compiled into the binary.
//!
//! These are the template sources a fresh installation starts from; a shop's own
//! versions are imported into the template library (`gearcam templates import`).

/// Every shipped template source: (file name, text), sorted by file name.
pub fn builtin_sources() -> Vec<(&'static str, &'static str)> {
    macro_rules! sources {
        ($($name:literal),* $(,)?) => {
            vec![$(($name, include_str!(concat!("../standard/", $name)))),*]
        };
    }
    sources![
        "conical_840d.tpl",
        "conical_fanuc.tpl",
        "crowned_840d.tpl",
        "crowned_fanuc.tpl",
        "cylindrical_840d.tpl",
        "cylindrical_fanuc.tpl",
        "multi_gear_840d.tpl",
        "multi_gear_fanuc.tpl",
        "worm_wheel_840d.tpl",
        "worm_wheel_fanuc.tpl",
    ]
}
