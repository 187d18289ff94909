//! The project's data for the JVRC-1 humanoid (URDF from the PyPI package `jvrc-description`
//! 1.1.1, located at run time; this module holds what the project adds to it).

/// The 12 finger joints, locked (at 0) in the project's setup; 10 of them mimic the thumbs.
pub const FINGER_JOINTS: [&str; 12] = [
    "R_UTHUMB",
    "R_LTHUMB",
    "R_UINDEX",
    "R_LINDEX",
    "R_ULITTLE",
    "R_LLITTLE",
    "L_UTHUMB",
    "L_LTHUMB",
    "L_UINDEX",
    "L_LINDEX",
    "L_ULITTLE",
    "L_LLITTLE",
];

/// The ankle frames that carry the soles.
pub const SOLE_PARENT_FRAMES: [&str; 2] = ["R_ANKLE_P_S", "L_ANKLE_P_S"];

/// The hand frames (wrist links).
pub const HAND_FRAMES: [&str; 2] = ["r_wrist", "l_wrist"];

/// A sole rectangle: its centre in the ankle frame and its half sizes (the project's
/// convention, as `stance_contact::Shape::Rectangle`); the rectangle's axes are the ankle
/// frame's axes, its normal the ankle frame's `+z` (pointing into the robot).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoleRectangle {
    /// The ankle frame name.
    pub frame: &'static str,
    /// Centre of the rectangle in that frame (m).
    pub center_in_ankle: [f64; 3],
    /// Half the length, along the ankle x axis (m).
    pub half_length: f64,
    /// Half the width, along the ankle y axis (m).
    pub half_width: f64,
}

/// JVRC-1's sole rectangles, 0.20 x 0.08 m, centred at (0.0303, -0.0012, -0.1077) in each
/// `*_ANKLE_P_S` frame (the same offset for both feet).
///
/// ```
/// let soles = stance_robot::jvrc1::sole_rectangles();
/// assert_eq!(soles[0].frame, "R_ANKLE_P_S");
/// assert_eq!((soles[1].half_length, soles[1].half_width), (0.10, 0.04));
/// ```
pub fn sole_rectangles() -> [SoleRectangle; 2] {
    SOLE_PARENT_FRAMES.map(|frame| SoleRectangle {
        frame,
        center_in_ankle: [0.0303, -0.0012, -0.1077],
        half_length: 0.10,
        half_width: 0.04,
    })
}

/// The options of the project's JVRC-1 setup: free flyer, fingers locked at 0.
///
/// ```
/// let o = stance_robot::jvrc1::urdf_options();
/// assert_eq!(o.locked.len(), 12);
/// ```
pub fn urdf_options() -> crate::UrdfOptions {
    crate::UrdfOptions {
        locked: FINGER_JOINTS.iter().map(|n| (n.to_string(), 0.0)).collect(),
        ..Default::default()
    }
}

/// Finds the JVRC-1 URDF of the PyPI package `jvrc-description`: the file named by the
/// environment variable `STANCE_JVRC1_URDF` if set, else the package's file in the virtualenv
/// `$STANCE_VENV` if set, else `<project_root>/.venv` ([`locate_urdf_in_venv`]). The reason when
/// it is not found (the caller says how to install it).
///
/// ```
/// // Without a virtualenv the answer says why.
/// match stance_robot::jvrc1::locate_urdf(Some(std::path::Path::new("no/such/root"))) {
///     Ok(path) => assert!(path.exists()),
///     Err(reason) => assert!(!reason.is_empty()),
/// }
/// ```
pub fn locate_urdf(project_root: Option<&std::path::Path>) -> Result<std::path::PathBuf, String> {
    use std::path::PathBuf;
    let venv = match (std::env::var_os("STANCE_VENV"), project_root) {
        (Some(v), _) if !v.is_empty() => PathBuf::from(v),
        (_, Some(root)) => root.join(".venv"),
        (_, None) if std::env::var_os("STANCE_JVRC1_URDF").is_some() => PathBuf::new(),
        (_, None) => return Err("neither STANCE_VENV nor a project root is given".into()),
    };
    locate_urdf_in_venv(&venv)
}

/// [`locate_urdf`] in the virtualenv `venv`: `STANCE_JVRC1_URDF` if set, else the package's file
/// in the virtualenv's site-packages, else the answer of its Python to "where is
/// `jvrc_description`".
pub fn locate_urdf_in_venv(venv: &std::path::Path) -> Result<std::path::PathBuf, String> {
    use std::path::PathBuf;
    if let Some(p) = std::env::var_os("STANCE_JVRC1_URDF") {
        let p = PathBuf::from(p);
        return if p.is_file() {
            Ok(p)
        } else {
            Err(format!("STANCE_JVRC1_URDF={} is not a file", p.display()))
        };
    }
    // The package's file in the virtualenv's site-packages, found without starting Python
    // (which costs tens of milliseconds).
    let lib = if cfg!(windows) {
        vec![venv.join("Lib")]
    } else {
        std::fs::read_dir(venv.join("lib"))
            .map(|d| d.flatten().map(|e| e.path()).collect())
            .unwrap_or_default()
    };
    for dir in lib {
        let candidate = dir
            .join("site-packages")
            .join("jvrc_description")
            .join("urdf")
            .join("jvrc1.urdf");
        if candidate.is_file() {
            return Ok(candidate);
        }
    }
    let python = if cfg!(windows) {
        venv.join("Scripts").join("python.exe")
    } else {
        venv.join("bin").join("python")
    };
    if !python.is_file() {
        return Err(format!("no Python virtualenv at {}", venv.display()));
    }
    let out = std::process::Command::new(&python)
        .args(["-c", "import jvrc_description as j; print(j.urdf_path)"])
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!(
            "the virtualenv at {} has no jvrc_description",
            venv.display()
        ));
    }
    let path = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if path.is_file() {
        Ok(path)
    } else {
        Err(format!(
            "jvrc_description points to {}, which is not a file",
            path.display()
        ))
    }
}
