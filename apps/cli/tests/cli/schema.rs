//! `sheetform schema`: the printed schemas match docs/schema/.

use crate::common::{repo, sheetform};

#[test]
fn schemas_are_printed_and_match_the_docs() {
    for (kind, file) in [
        ("bend", "bend-scene"),
        ("slit", "slit-scene"),
        ("ffd", "ffd-scene"),
        ("photo", "photo-annotation"),
        ("report", "report"),
    ] {
        let o = sheetform(&["schema", kind]);
        assert!(o.status.success());
        let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let file = format!("docs/schema/{file}.schema.json");
        let documented: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(repo().join(&file)).unwrap()).unwrap();
        assert_eq!(
            printed, documented,
            "{file} is stale: regenerate with `sheetform schema {kind} > {file}`"
        );
    }
}
