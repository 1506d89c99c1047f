//! Key files and signatures: a key pair written and read back (private and public), a
//! signature that holds for its image only, a `.sig` file of the wrong length refused.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use bridge_update::keys;

#[test]
fn a_key_pair_round_trips_and_signs_only_its_image() {
    let dir = std::env::temp_dir().join(format!("bridge-update-keys-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let path = dir.join("update-key.pem");
    let key = keys::generate();
    keys::write_key_pair(&path, &key).unwrap();
    assert_eq!(keys::public_path(&path), dir.join("update-key.pub.pem"));
    let read = keys::read_signing_key(&path).unwrap();
    assert_eq!(read.to_bytes(), key.to_bytes());
    // The public key from its own file and from the private key's.
    for p in [keys::public_path(&path), path.clone()] {
        assert_eq!(keys::read_public_key(&p).unwrap(), key.verifying_key());
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600, "the private key is its owner's only");
    }
    let image = b"an image".repeat(100);
    let sig = keys::sign(&key, &image);
    assert_eq!(sig.len(), keys::SIG_FILE_LEN);
    let (signature, signer) = keys::parse_sig(&sig).unwrap();
    assert_eq!(&signer, key.verifying_key().as_bytes());
    assert!(keys::verify(&signer, &image, &signature));
    let mut other = image.clone();
    other[5] ^= 1;
    assert!(!keys::verify(&signer, &other, &signature));
    assert!(keys::parse_sig(&sig[..95]).is_err());
    assert!(
        keys::read_signing_key(&keys::public_path(&path)).is_err(),
        "a public key is no private key"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
