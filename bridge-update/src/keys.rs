//! Signing keys and signed images, on the host (feature `keys`).
//!
//! - The integrator's key is an ed25519 private key in a PKCS#8 PEM file, as
//!   `openssl genpkey -algorithm ed25519 -out update-key.pem` writes it (or
//!   `gimbal update-key KEY.pem`); its public half is an SPKI PEM file
//!   (`openssl pkey -in update-key.pem -pubout`). The firmware is built with the public
//!   key (`BRIDGE_UPDATE_KEY`), images are signed with the private one.
//! - Without one, the development key is used: generated on first use in the user's
//!   configuration directory ([`dev_key_path`]), never in the source tree, and reported as
//!   a development key by the board and the tools.
//! - A signature is ed25519 over the image's SHA-512 (embassy-boot's convention: its own
//!   `verify_and_mark_updated` checks the same signature). It is kept beside the image as
//!   `IMAGE.sig`: the 64-byte signature, then the signer's 32-byte public key (for the
//!   client's early, readable "wrong key" message; the board trusts only its own key).

extern crate std;

use std::format;
use std::fs;
use std::path::{Path, PathBuf};
use std::string::{String, ToString};
use std::vec::Vec;

use ed25519_dalek::pkcs8::{DecodePrivateKey, DecodePublicKey, EncodePrivateKey, EncodePublicKey};
use ed25519_dalek::{Signer, SigningKey, VerifyingKey, pkcs8::spki::der::pem::LineEnding};
use sha2::{Digest, Sha512};

use crate::wire::SIGNATURE_LEN;

/// Bytes of a `.sig` file: the signature, then the signer's public key.
pub const SIG_FILE_LEN: usize = SIGNATURE_LEN + 32;

/// A new random key.
#[must_use]
pub fn generate() -> SigningKey {
    SigningKey::generate(&mut rand_core::OsRng)
}

/// Reads a private key (PKCS#8 PEM).
///
/// # Errors
/// The file cannot be read or holds no ed25519 private key.
pub fn read_signing_key(path: &Path) -> Result<SigningKey, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    SigningKey::from_pkcs8_pem(&text).map_err(|e| {
        format!(
            "{}: not an ed25519 private key in PKCS#8 PEM ({e})",
            path.display()
        )
    })
}

/// Reads a public key: an SPKI PEM file, or the public half of a PKCS#8 private key file.
///
/// # Errors
/// The file cannot be read or holds no ed25519 key.
pub fn read_public_key(path: &Path) -> Result<VerifyingKey, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if let Ok(key) = VerifyingKey::from_public_key_pem(&text) {
        return Ok(key);
    }
    SigningKey::from_pkcs8_pem(&text)
        .map(|k| k.verifying_key())
        .map_err(|_| {
            format!(
                "{}: not an ed25519 public key (SPKI PEM) or private key (PKCS#8 PEM)",
                path.display()
            )
        })
}

/// Writes a private key (PKCS#8 PEM, readable by its owner only) and its public half beside
/// it ([`public_path`]).
///
/// # Errors
/// A file cannot be written.
pub fn write_key_pair(path: &Path, key: &SigningKey) -> Result<(), String> {
    let private = key
        .to_pkcs8_pem(LineEnding::LF)
        .map_err(|e| e.to_string())?;
    let public = key
        .verifying_key()
        .to_public_key_pem(LineEnding::LF)
        .map_err(|e| e.to_string())?;
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let tmp = path.with_extension("pem.tmp");
    write_private(&tmp, private.as_bytes())?;
    fs::write(public_path(path), public).map_err(|e| format!("{}: {e}", path.display()))?;
    // Renamed last: a key file that exists is complete, even with builds racing.
    fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(unix)]
fn write_private(path: &Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .mode(0o600)
        .open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    f.write_all(bytes)
        .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(not(unix))]
fn write_private(path: &Path, bytes: &[u8]) -> Result<(), String> {
    fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The public key file beside a private key file: `KEY.pub.pem` for `KEY.pem`.
#[must_use]
pub fn public_path(private: &Path) -> PathBuf {
    let stem = private
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    private.with_file_name(format!("{stem}.pub.pem"))
}

/// Where the development key lives: `$XDG_CONFIG_HOME/k40t-bridge/update-key-dev.pem`
/// (`~/.config/...` without it): outside every source tree, one per user.
#[must_use]
pub fn dev_key_path() -> PathBuf {
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))
        .unwrap_or_else(|| PathBuf::from("."));
    config.join("k40t-bridge").join("update-key-dev.pem")
}

/// The development key: read, or generated on first use (`true`: just generated).
///
/// # Errors
/// The key cannot be read or written.
pub fn dev_key() -> Result<(SigningKey, bool), String> {
    let path = dev_key_path();
    if path.exists() {
        return read_signing_key(&path).map(|k| (k, false));
    }
    let key = generate();
    write_key_pair(&path, &key)?;
    // Another build may have won the race: use what is on disk.
    read_signing_key(&path).map(|k| (k, true))
}

/// Whether `public` is the development key's.
#[must_use]
pub fn is_dev_key(public: &VerifyingKey) -> bool {
    read_public_key(&public_path(&dev_key_path())).is_ok_and(|k| k == *public)
}

/// The SHA-512 of an image: what is signed.
#[must_use]
pub fn digest(image: &[u8]) -> [u8; 64] {
    Sha512::digest(image).into()
}

/// Signs an image: the `.sig` file's bytes (signature, then the public key).
#[must_use]
pub fn sign(key: &SigningKey, image: &[u8]) -> Vec<u8> {
    let signature = key.sign(&digest(image));
    let mut out = Vec::with_capacity(SIG_FILE_LEN);
    out.extend_from_slice(&signature.to_bytes());
    out.extend_from_slice(key.verifying_key().as_bytes());
    out
}

/// A `.sig` file's signature and signer.
///
/// # Errors
/// Not [`SIG_FILE_LEN`] bytes.
pub fn parse_sig(bytes: &[u8]) -> Result<([u8; SIGNATURE_LEN], [u8; 32]), String> {
    let (sig, key) = bytes.split_at_checked(SIGNATURE_LEN).ok_or_else(|| {
        format!(
            "a signature file is {SIG_FILE_LEN} bytes, not {}",
            bytes.len()
        )
    })?;
    let sig: [u8; SIGNATURE_LEN] = sig.try_into().map_err(|_| "short signature".to_string())?;
    let key: [u8; 32] = key.try_into().map_err(|_| {
        format!(
            "a signature file is {SIG_FILE_LEN} bytes, not {}",
            bytes.len()
        )
    })?;
    Ok((sig, key))
}

/// Whether `sig` is a good signature of `image` by `public`.
#[must_use]
pub fn verify(public: &[u8; 32], image: &[u8], sig: &[u8; SIGNATURE_LEN]) -> bool {
    VerifyingKey::from_bytes(public)
        .and_then(|k| k.verify_strict(&digest(image), &ed25519_dalek::Signature::from_bytes(sig)))
        .is_ok()
}
