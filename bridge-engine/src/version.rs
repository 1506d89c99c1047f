//! The bridge's version: one semantic version (the workspace's `version` in Cargo.toml,
//! as every crate's `CARGO_PKG_VERSION`), the commit the image was built from and its
//! build's features ([`BuildInfo`]), and its forms in the protocols that carry a firmware
//! version (docs/src/firmware/configuration.md#versions):
//!
//! | where | form | method |
//! | --- | --- | --- |
//! | SIYI 0x01 firmware version | camera, gimbal and zoom: the version (patch, minor, major, 0 on the wire); ArduPilot waits for a non-zero camera version | [`Version::is_zero`] |
//! | Viewlink 0xD0 firmware text | `S20MMmmpp` (ArduPilot reads MM.mm.pp), each part at most 99 | [`Version::viewlink_text`] |
//! | GCU reply byte 39 | firmware × 10: major × 10 + minor (minor at most 9) | [`Version::gcu_x10`] |
//! | GIMBAL_DEVICE_INFORMATION, CAMERA_INFORMATION `firmware_version` | byte 0 major, 1 minor, 2 patch, 3 dev (0) | [`Version::mavlink`] |
//! | AUTOPILOT_VERSION `flight_sw_version` | major, minor, patch, FIRMWARE_VERSION_TYPE from the high byte down | [`BuildInfo::flight_sw_version`] |
//! | AUTOPILOT_VERSION `flight_custom_version` | the commit's first 8 hexadecimal digits, as text | [`BuildInfo::custom_version`] |
//!
//! The engine only reports what its caller built it with ([`Engine::with_build`](crate::Engine::with_build)):
//! the firmware's and the host tool's build scripts know the commit and the features.

use core::fmt;

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A semantic version's numbers: `MAJOR.MINOR.PATCH`, each 0..=255 (every protocol
    /// above carries a byte per part), and whether it had a pre-release part (`-rc.1`).
    pub struct Version {
        /// Major.
        pub major: u8,
        /// Minor.
        pub minor: u8,
        /// Patch.
        pub patch: u8,
        /// A pre-release (`1.0.0-rc.1`): a development build.
        pub pre_release: bool,
    }
}

/// The decimal number at the start of `t`, 0..=255, without a leading zero (semver's
/// rule), and what follows it. Slice patterns only: `const`, and no index to check.
const fn number(t: &[u8]) -> Option<(u8, &[u8])> {
    let mut value: u16 = 0;
    let mut digits: u8 = 0;
    let mut rest = t;
    while let [c @ b'0'..=b'9', r @ ..] = rest {
        // At most 255 before this step: at most 2559 after it.
        value = value
            .wrapping_mul(10)
            .wrapping_add(c.wrapping_sub(b'0') as u16);
        if value > 255 {
            return None;
        }
        digits = digits.saturating_add(1);
        rest = r;
    }
    let leading_zero = matches!(t, [b'0', ..]) && digits > 1;
    if digits == 0 || leading_zero {
        return None;
    }
    #[allow(clippy::cast_possible_truncation)] // at most 255
    Some((value as u8, rest))
}

impl Version {
    /// The numbers of a semantic version's text (`0.2.0`, `1.0.0-rc.1`, `1.2.3+build.5`);
    /// `None` when it is not one, or a part is above 255. `const`, so that a build checks
    /// its `CARGO_PKG_VERSION` at compile time.
    #[must_use]
    pub const fn parse(text: &str) -> Option<Self> {
        let Some((major, t)) = number(text.as_bytes()) else {
            return None;
        };
        let [b'.', t @ ..] = t else {
            return None;
        };
        let Some((minor, t)) = number(t) else {
            return None;
        };
        let [b'.', t @ ..] = t else {
            return None;
        };
        let Some((patch, t)) = number(t) else {
            return None;
        };
        let pre_release = match t {
            [] | [b'+', _, ..] => false,
            [b'-', _, ..] => true,
            _ => return None,
        };
        Some(Version {
            major,
            minor,
            patch,
            pre_release,
        })
    }

    /// `firmware_version` of GIMBAL_DEVICE_INFORMATION and CAMERA_INFORMATION: byte 0
    /// major, 1 minor, 2 patch, 3 the "dev" byte (0).
    #[must_use]
    pub const fn mavlink(self) -> u32 {
        u32::from_le_bytes([self.major, self.minor, self.patch, 0])
    }

    /// All three parts zero (ArduPilot's SIYI driver waits for a non-zero version).
    #[must_use]
    pub const fn is_zero(self) -> bool {
        self.major == 0 && self.minor == 0 && self.patch == 0
    }

    /// The Viewlink 0xD0 firmware text: `S20MMmmpp` (a Viewpro date-like text, "S" and
    /// `yyyymmdd`, that ArduPilot reads from byte 3 as three two-digit numbers), padded
    /// with zeros; a part above 99 is sent as 99.
    #[must_use]
    pub fn viewlink_text(self) -> [u8; 20] {
        let mut text = [0u8; 20];
        let digits = [self.major, self.minor, self.patch]
            .map(|p| p.min(99))
            .map(|p| [b'0'.wrapping_add(p / 10), b'0'.wrapping_add(p % 10)]);
        for (slot, b) in text
            .iter_mut()
            .zip(b"S20".iter().chain(digits.as_flattened()))
        {
            *slot = *b;
        }
        text
    }

    /// The GCU reply's firmware version, times ten (byte 39; ArduPilot prints it divided
    /// by 10): major × 10 + minor, with a minor above 9 as 9 and at most 255 (25.5). The
    /// patch is not carried.
    #[must_use]
    pub const fn gcu_x10(self) -> u8 {
        let minor = if self.minor > 9 { 9 } else { self.minor };
        self.major.saturating_mul(10).saturating_add(minor)
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// What an image is: its version, the commit it was built from and its build's
    /// features. Displays as one line, `0.2.0 commit 9e3aa0d1c2b4-dirty, hw: fc-siyi
    /// telemetry` (what `gimbal --version`, the firmware's boot log and the console print).
    pub struct BuildInfo {
        /// The numbers of [`BuildInfo::semver`].
        pub version: Version,
        /// The semantic version as written in Cargo.toml (`0.2.0`).
        pub semver: &'static str,
        /// The commit: its first 12 hexadecimal digits, or `unknown` (built outside a git
        /// checkout, as `cargo install` from a package).
        pub commit: &'static str,
        /// The checkout had uncommitted changes to tracked files when it was built.
        pub dirty: bool,
        /// Where it runs: `hw` (the board), `qemu` (the emulated board), `host` (the
        /// firmware's tasks on Linux: `gimbal`).
        pub flavour: &'static str,
        /// The FC sides and links compiled in, space-separated (`fc-siyi fc-mavlink
        /// telemetry`).
        pub features: &'static str,
    }
}

/// This crate's version (the workspace's).
const ENGINE_VERSION: Option<Version> = Version::parse(env!("CARGO_PKG_VERSION"));
const _: () = assert!(
    ENGINE_VERSION.is_some(),
    "the workspace's version must be MAJOR.MINOR.PATCH, each 0..=255"
);
// A SIYI autopilot waits for a non-zero camera version: the bridge's is never zero.
const _: () = assert!(match ENGINE_VERSION {
    Some(v) => !v.is_zero(),
    None => false,
});

/// FIRMWARE_VERSION_TYPE values (AUTOPILOT_VERSION's low byte).
mod firmware_type {
    pub(super) const DEV: u8 = 0;
    pub(super) const OFFICIAL: u8 = 255;
}

impl BuildInfo {
    /// The engine's own version with nothing else known: what [`Engine::new`](crate::Engine::new)
    /// reports until a caller says more ([`Engine::with_build`](crate::Engine::with_build)).
    pub const ENGINE: Self = Self {
        version: match ENGINE_VERSION {
            Some(v) => v,
            None => Version {
                major: 0,
                minor: 0,
                patch: 0,
                pre_release: true,
            },
        },
        semver: env!("CARGO_PKG_VERSION"),
        commit: "unknown",
        dirty: false,
        flavour: "",
        features: "",
    };

    /// A release build: no pre-release part, built from a commit without changes.
    #[must_use]
    pub const fn is_release(&self) -> bool {
        !self.version.pre_release && !self.dirty
    }

    /// AUTOPILOT_VERSION's `flight_sw_version`: major, minor, patch and the
    /// FIRMWARE_VERSION_TYPE (OFFICIAL for a release, DEV otherwise), from the most
    /// significant byte down.
    #[must_use]
    pub const fn flight_sw_version(&self) -> u32 {
        let kind = if self.is_release() {
            firmware_type::OFFICIAL
        } else {
            firmware_type::DEV
        };
        let v = self.version;
        u32::from_be_bytes([v.major, v.minor, v.patch, kind])
    }

    /// AUTOPILOT_VERSION's `flight_custom_version`: the commit's first 8 hexadecimal
    /// digits as text (as ArduPilot fills it), zeros when the commit is unknown.
    #[must_use]
    pub fn custom_version(&self) -> [u8; 8] {
        let mut out = [0u8; 8];
        let c = self.commit.as_bytes();
        if c.len() >= out.len() && c.iter().all(u8::is_ascii_hexdigit) {
            for (d, s) in out.iter_mut().zip(c) {
                *d = *s;
            }
        }
        out
    }
}

impl fmt::Display for BuildInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} commit {}", self.semver, self.commit)?;
        if self.dirty {
            f.write_str("-dirty")?;
        }
        match (self.flavour, self.features) {
            ("", "") => Ok(()),
            (flavour, "") => write!(f, ", {flavour}"),
            (flavour, features) => write!(f, ", {flavour}: {features}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::string::ToString;

    const fn v(major: u8, minor: u8, patch: u8) -> Version {
        Version {
            major,
            minor,
            patch,
            pre_release: false,
        }
    }

    #[test]
    fn semantic_versions_parse() {
        assert_eq!(Version::parse("0.2.0"), Some(v(0, 2, 0)));
        assert_eq!(Version::parse("255.10.9+build.7"), Some(v(255, 10, 9)));
        let rc = Version::parse("1.0.0-rc.1").unwrap();
        assert_eq!(
            (rc.major, rc.minor, rc.patch, rc.pre_release),
            (1, 0, 0, true)
        );
        for bad in [
            "", "1", "1.2", "1.2.3.4", "1..3", "1.2.", ".1.2", "01.2.3", "1.2.256", "a.b.c",
            "1.2.3-", "1.2.3+", "1.2.-3",
        ] {
            assert_eq!(Version::parse(bad), None, "{bad:?}");
        }
        assert_eq!(
            BuildInfo::ENGINE.version,
            Version::parse(env!("CARGO_PKG_VERSION")).unwrap()
        );
    }

    #[test]
    fn each_protocol_form() {
        let x = v(1, 12, 3);
        assert_eq!(x.mavlink().to_le_bytes(), [1, 12, 3, 0]);
        assert_eq!(&x.viewlink_text()[..10], b"S20011203\0");
        assert_eq!(&v(100, 7, 250).viewlink_text()[..9], b"S20990799");
        assert_eq!(x.gcu_x10(), 19, "1.12 is carried as 1.9");
        assert_eq!(v(0, 2, 0).gcu_x10(), 2);
        assert_eq!(v(30, 0, 0).gcu_x10(), 255);
        assert!(v(0, 0, 0).is_zero() && !v(0, 0, 1).is_zero());
    }

    #[test]
    fn the_build_line_and_autopilot_version() {
        let mut b = BuildInfo {
            version: v(0, 2, 0),
            semver: "0.2.0",
            commit: "9e3aa0d1c2b4",
            dirty: false,
            flavour: "hw",
            features: "fc-siyi telemetry",
        };
        assert_eq!(
            b.to_string(),
            "0.2.0 commit 9e3aa0d1c2b4, hw: fc-siyi telemetry"
        );
        assert_eq!(b.flight_sw_version(), 0x0002_00FF);
        assert_eq!(&b.custom_version(), b"9e3aa0d1");
        b.dirty = true;
        assert_eq!(b.flight_sw_version(), 0x0002_0000);
        assert_eq!(
            b.to_string(),
            "0.2.0 commit 9e3aa0d1c2b4-dirty, hw: fc-siyi telemetry"
        );
        b.features = "";
        assert_eq!(b.to_string(), "0.2.0 commit 9e3aa0d1c2b4-dirty, hw");
        assert_eq!(
            BuildInfo::ENGINE.to_string(),
            std::format!("{} commit unknown", env!("CARGO_PKG_VERSION"))
        );
        assert_eq!(BuildInfo::ENGINE.custom_version(), [0; 8]);
    }
}
