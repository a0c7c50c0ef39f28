//! Item 6: everything the check knows comes from the registry. For every function the
//! registry declares, a call with as few and as many values as it takes checks clean, one
//! value more (or one fewer) is E102; the `.luacheckrc` names every function's global.

use check::{Checker, Environment, Options};

#[test]
fn every_registry_function_is_checked_with_its_own_count() {
    let checker = Checker::new(Options::default());
    let rc = check::luacheckrc::generate(&Environment::new());
    let mut wrong = Vec::new();
    let mut functions = 0;
    for spec in api::registry::all() {
        functions += 1;
        let call = |n: usize| format!("local v = ...\n{}({})\n", spec.name, vec!["v"; n].join(", "));
        let codes =
            |n: usize| -> Vec<&str> { checker.check_source("t.lua", &call(n), None).iter().map(|d| d.code).collect() };
        let (min, max) = (spec.min_args(), spec.max_args());
        for n in [Some(min), max].into_iter().flatten() {
            if !codes(n).is_empty() {
                wrong.push(format!("{} with {n}: {:?}", spec.name, codes(n)));
            }
        }
        if let Some(max) = max
            && codes(max + 1) != ["E102"]
        {
            wrong.push(format!("{} with {}: {:?}", spec.name, max + 1, codes(max + 1)));
        }
        if min > 0 && codes(min - 1) != ["E102"] {
            wrong.push(format!("{} with {}: {:?}", spec.name, min - 1, codes(min - 1)));
        }
        let root = spec.name.split('.').next().unwrap();
        if !rc.contains(&format!("\"{root}\"")) {
            wrong.push(format!("{root} is not in the .luacheckrc"));
        }
    }
    assert!(functions >= 340, "{functions} functions");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
