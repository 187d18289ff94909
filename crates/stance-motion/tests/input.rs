//! Input files name every field: the array form serde's derived structs also accept (values in
//! declaration order) is refused at every depth, in JSON and TOML, with a message saying what to
//! write instead; the named forms still read.

use stance_contact::Scene;

fn dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("stance-input-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn read(name: &str, text: &str) -> Result<Scene, String> {
    let p = dir().join(name);
    std::fs::write(&p, text).unwrap();
    stance_motion::input::read_file::<Scene>(&p).map_err(|e| e.to_string())
}

const CONTACT: &str = r#"{"name": "LF", "position": [0, 0, 0], "shape": {"rectangle": {"half_length": 0.11, "half_width": 0.065}}, "friction": 0.7}"#;

#[test]
fn named_fields_read() {
    let s = read(
        "ok.json",
        &format!(r#"{{"mass": 39, "contacts": [{CONTACT}]}}"#),
    )
    .unwrap();
    assert_eq!(s.contacts.len(), 1);
    let t = read(
        "ok.toml",
        "mass = 39\n[[contacts]]\nname = \"LF\"\nposition = [0, 0, 0]\nfriction = 0.7\n\
         shape = { rectangle = { half_length = 0.11, half_width = 0.065 } }\n",
    )
    .unwrap();
    assert_eq!(t, s);
}

#[test]
fn array_forms_of_structs_are_refused_at_every_depth() {
    let cases = [
        // the scene itself
        (
            "top.json",
            format!(r#"[39, [0, 0, -9.81], [{CONTACT}], {{"sides": 4}}]"#),
            "Scene",
        ),
        // a contact
        (
            "contact.json",
            r#"{"mass": 39, "contacts": [["LF", [0, 0, 0], [[1,0,0],[0,1,0],[0,0,1]], "point", 0.7]]}"#
                .to_string(),
            "ContactSpec",
        ),
        // a struct variant
        (
            "variant.json",
            r#"{"mass": 39, "contacts": [{"name": "LF", "position": [0, 0, 0], "shape": {"rectangle": [0.11, 0.065]}, "friction": 0.7}]}"#
                .to_string(),
            "variant",
        ),
        // the friction model
        (
            "model.json",
            format!(r#"{{"mass": 39, "contacts": [{CONTACT}], "friction_model": [4, "outer"]}}"#),
            "FrictionModel",
        ),
    ];
    for (name, text, what) in cases {
        let e = read(name, &text).unwrap_err();
        assert!(
            e.contains(what) && e.contains("object with named fields"),
            "{name}: {e}"
        );
    }
    let e = read(
        "contact.toml",
        "mass = 39\ncontacts = [[\"LF\", [0, 0, 0], [[1,0,0],[0,1,0],[0,0,1]], \"point\", 0.7]]\n",
    )
    .unwrap_err();
    assert!(e.contains("object with named fields"), "{e}");
}

#[test]
fn trailing_text_after_the_object_is_an_error() {
    let e = read(
        "trail.json",
        &format!(r#"{{"mass": 39, "contacts": [{CONTACT}]}} x"#),
    )
    .unwrap_err();
    assert!(e.contains("trailing"), "{e}");
}

/// A TOML error is one line that says where (line, column and the line itself), which key,
/// and what is wrong: the key path as in JSON's messages.
#[test]
fn toml_errors_name_the_line_and_the_key() {
    let e = read(
        "wrong-type.toml",
        "mass = 39\n[[contacts]]\nname = \"LF\"\nposition = [0, 0, \"up\"]\nfriction = 0.7\n",
    )
    .unwrap_err();
    assert!(!e.contains('\n'), "{e}");
    assert!(
        e.contains("wrong-type.toml")
            && e.contains("line 4, column 19")
            && e.contains("(`position = [0, 0, \"up\"]`)")
            && e.contains("key `contacts[0].position[2]`")
            && e.contains("invalid type"),
        "{e}"
    );
    let e = read("syntax.toml", "mass = 39\nname = \"LF\n").unwrap_err();
    assert!(e.contains("line 2") && e.contains("`name = \"LF`"), "{e}");
    // the same key path as the JSON file's message
    let j = read(
        "wrong-type.json",
        r#"{"mass": 39, "contacts": [{"name": "LF", "position": [0, 0, "up"], "friction": 0.7}]}"#,
    )
    .unwrap_err();
    assert!(j.contains("key `contacts[0].position[2]`"), "{j}");
}
