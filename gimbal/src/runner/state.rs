//! `gimbal bridge --state-dir`: the engine's persistent records (`bridge_engine::store`: the
//! signing timestamp and a key set by SETUP_SIGNING) in one state file, as the firmware
//! keeps them in flash. The engine decides what and when; this only moves the bytes.
//!
//! - **Where.** `DIR/state.bin`; `DIR` is `--state-dir`, by default
//!   `$XDG_STATE_HOME/k40t-bridge`, else `~/.local/state/k40t-bridge` (created, mode 0700;
//!   the file is 0600: it may hold a signing key).
//! - **Format.** `K40T-BRIDGE-STATE` and a version byte (1), then each record: its key
//!   (u16, little-endian), its length (a byte), its value, and a CRC-32 (ISO-HDLC, as
//!   zlib's) of the key, the length and the value.
//! - **Writing.** Every save writes the whole file anew: a temporary file in the same
//!   directory, written, flushed to the disk (`fsync`), renamed over the old one, the
//!   directory flushed: a crash leaves the old file or the new one, never half of one.
//! - **A file that cannot be read or is corrupt** (its header, a length past the end, a
//!   CRC) is kept aside for the technician, renamed `state.bin.bad-SECONDS` (Unix time),
//!   and the bridge starts on its defaults, saying so (the engine's `store_record` event
//!   for the whole store, and a `state_file_set_aside` event naming the file).

use std::collections::BTreeMap;
use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

use bridge_fw::RecordStore;

/// The file's first bytes.
const MAGIC: &[u8] = b"K40T-BRIDGE-STATE";
/// The format's version.
const VERSION: u8 = 1;
/// The state file's name in its directory.
pub const FILE: &str = "state.bin";
/// CRC-32 of each record.
const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// The default state directory: `$XDG_STATE_HOME/k40t-bridge`, else
/// `$HOME/.local/state/k40t-bridge` (`None`: neither is set).
#[must_use]
pub fn default_dir() -> Option<PathBuf> {
    let xdg = std::env::var_os("XDG_STATE_HOME").filter(|v| !v.is_empty());
    let base = match xdg {
        Some(x) => PathBuf::from(x),
        None => PathBuf::from(std::env::var_os("HOME").filter(|v| !v.is_empty())?)
            .join(".local")
            .join("state"),
    };
    Some(base.join("k40t-bridge"))
}

/// The records and the file they live in.
#[derive(Debug)]
pub struct StateFile {
    path: PathBuf,
    records: BTreeMap<u16, Vec<u8>>,
}

/// What opening the state file found wrong: the file was set aside (to `aside`, when the
/// rename worked) and the bridge starts on its defaults.
#[derive(Debug)]
pub struct SetAside {
    /// What was wrong.
    pub problem: String,
    /// Where the bad file now is.
    pub aside: Option<PathBuf>,
}

/// The records of a state file's bytes.
///
/// # Errors
/// What is wrong with them.
pub fn decode(bytes: &[u8]) -> Result<BTreeMap<u16, Vec<u8>>, String> {
    let rest = bytes
        .strip_prefix(MAGIC)
        .ok_or("not a state file (its header)")?;
    let (&version, mut rest) = rest.split_first().ok_or("no version")?;
    if version != VERSION {
        return Err(format!("format version {version}, not {VERSION}"));
    }
    let mut records = BTreeMap::new();
    while !rest.is_empty() {
        let [k0, k1, len, tail @ ..] = rest else {
            return Err("a record's head cut short".into());
        };
        let n = usize::from(*len);
        let (value, tail) = tail
            .split_at_checked(n)
            .ok_or("a record's value cut short")?;
        let (crc, tail) = tail.split_at_checked(4).ok_or("a record's CRC cut short")?;
        let head = [*k0, *k1, *len];
        let mut digest = CRC.digest();
        digest.update(&head);
        digest.update(value);
        if digest.finalize().to_le_bytes() != crc {
            return Err(format!(
                "the CRC of record 0x{:04x}",
                u16::from_le_bytes([*k0, *k1])
            ));
        }
        records.insert(u16::from_le_bytes([*k0, *k1]), value.to_vec());
        rest = tail;
    }
    Ok(records)
}

/// The bytes of a state file holding `records`.
#[must_use]
pub fn encode(records: &BTreeMap<u16, Vec<u8>>) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.push(VERSION);
    for (key, value) in records {
        let Ok(len) = u8::try_from(value.len()) else {
            continue;
        };
        let [k0, k1] = key.to_le_bytes();
        let head = [k0, k1, len];
        let mut digest = CRC.digest();
        digest.update(&head);
        digest.update(value);
        out.extend_from_slice(&head);
        out.extend_from_slice(value);
        out.extend_from_slice(&digest.finalize().to_le_bytes());
    }
    out
}

impl StateFile {
    /// Opens (or starts) the state file in `dir`, creating the directory. A file that
    /// cannot be read or decoded is set aside: the store starts empty, and the second
    /// value says what happened.
    ///
    /// # Errors
    /// The directory cannot be created.
    pub fn open(dir: &Path) -> Result<(Self, Option<SetAside>), String> {
        fs::create_dir_all(dir).map_err(|e| format!("--state-dir {}: {e}", dir.display()))?;
        // Owner only: the file may hold a signing key. Best effort on a directory the
        // user chose and may share.
        let _ = fs::set_permissions(dir, fs::Permissions::from_mode(0o700));
        let path = dir.join(FILE);
        let read = match fs::read(&path) {
            Ok(bytes) => decode(&bytes).map(Some),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e.to_string()),
        };
        match read {
            Ok(records) => Ok((
                StateFile {
                    path,
                    records: records.unwrap_or_default(),
                },
                None,
            )),
            Err(problem) => {
                let secs = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs());
                let aside = dir.join(format!("{FILE}.bad-{secs}"));
                let aside = fs::rename(&path, &aside).ok().map(|()| aside);
                Ok((
                    StateFile {
                        path,
                        records: BTreeMap::new(),
                    },
                    Some(SetAside { problem, aside }),
                ))
            }
        }
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the records: a temporary file, flushed, renamed over the file, the directory
    /// flushed.
    fn write(&self) -> io::Result<()> {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        let tmp = self
            .path
            .with_extension(format!("bin.tmp-{}", std::process::id()));
        let mut f = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o600)
            .open(&tmp)?;
        f.write_all(&encode(&self.records))?;
        f.sync_all()?;
        drop(f);
        fs::rename(&tmp, &self.path)?;
        File::open(dir)?.sync_all()
    }
}

impl RecordStore for StateFile {
    async fn load(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, ()> {
        Ok(self.records.get(&key).map(|v| {
            let n = v.len().min(buf.len());
            buf[..n].copy_from_slice(&v[..n]);
            n
        }))
    }

    async fn save(&mut self, key: u16, value: &[u8]) -> Result<(), ()> {
        self.records.insert(key, value.to_vec());
        self.write().map_err(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embassy_futures::block_on;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("k40t-state-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn records_survive_a_restart_in_one_file() {
        let d = dir("restart");
        let (mut s, problem) = StateFile::open(&d).unwrap();
        assert!(problem.is_none());
        block_on(s.save(1, &[1, 2, 3])).unwrap();
        block_on(s.save(0x11, &[7; 40])).unwrap();
        block_on(s.save(1, &[4, 5, 6])).unwrap();
        let mode = fs::metadata(s.path()).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
        let (mut again, problem) = StateFile::open(&d).unwrap();
        assert!(problem.is_none());
        let mut buf = [0u8; 64];
        assert_eq!(block_on(again.load(1, &mut buf)), Ok(Some(3)));
        assert_eq!(&buf[..3], &[4, 5, 6]);
        assert_eq!(block_on(again.load(0x11, &mut buf)), Ok(Some(40)));
        assert_eq!(block_on(again.load(2, &mut buf)), Ok(None));
        let left: Vec<_> = fs::read_dir(&d).unwrap().collect();
        assert_eq!(left.len(), 1, "the state file alone: {left:?}");
        fs::remove_dir_all(&d).unwrap();
    }

    /// Every cut of a good file, and every byte changed, is found corrupt (or, cut at a
    /// record's end, a shorter good file); a corrupt file is set aside.
    #[test]
    fn a_corrupt_file_is_set_aside_and_the_store_starts_empty() {
        let mut records = BTreeMap::new();
        records.insert(1u16, vec![1u8; 7]);
        records.insert(0x11u16, vec![2u8; 40]);
        let good = encode(&records);
        assert_eq!(decode(&good).unwrap(), records);
        for n in 0..good.len() {
            if let Ok(r) = decode(&good[..n]) {
                assert!(r.len() < records.len(), "cut at {n}");
            }
        }
        for i in 0..good.len() {
            let mut bad = good.clone();
            bad[i] ^= 0x10;
            assert!(decode(&bad).is_err(), "byte {i} changed");
        }
        let d = dir("corrupt");
        fs::create_dir_all(&d).unwrap();
        fs::write(d.join(FILE), &good[..good.len() - 1]).unwrap();
        let (mut s, problem) = StateFile::open(&d).unwrap();
        let problem = problem.expect("corrupt");
        assert!(problem.problem.contains("cut short"), "{}", problem.problem);
        let aside = problem.aside.expect("renamed");
        assert_eq!(fs::read(&aside).unwrap(), &good[..good.len() - 1]);
        let mut buf = [0u8; 64];
        assert_eq!(block_on(s.load(1, &mut buf)), Ok(None));
        assert!(!d.join(FILE).exists());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_default_directory_follows_xdg() {
        let d = default_dir().expect("HOME or XDG_STATE_HOME");
        assert!(d.ends_with("k40t-bridge"));
    }
}
