//! The checksums the four protocols use.
//!
//! CRCs come from the `crc` crate's catalogue (table-driven, computed at compile time).
//! Check values over ASCII `"123456789"`: MCRF4XX `0x6F91`, XMODEM `0x31C3`.

use crc::{CRC_16_MCRF4XX, CRC_16_XMODEM, Crc};

/// CRC-16/MCRF4XX, the "X.25" of the K40T document (init 0xFFFF, reflected poly 0x1021,
/// no final xor; MAVLink's `crc_accumulate`). Not CRC-16/IBM-SDLC, which has a final xor.
pub const MCRF4XX: Crc<u16> = Crc::<u16>::new(&CRC_16_MCRF4XX);

/// CRC-16/XMODEM (init 0, poly 0x1021, not reflected), used by SIYI and GCU.
pub const XMODEM: Crc<u16> = Crc::<u16>::new(&CRC_16_XMODEM);

/// CRC-16/MCRF4XX of `data`.
#[must_use]
pub fn crc16_mcrf4xx(data: &[u8]) -> u16 {
    MCRF4XX.checksum(data)
}

/// CRC-16/XMODEM of `data`.
#[must_use]
pub fn crc16_xmodem(data: &[u8]) -> u16 {
    XMODEM.checksum(data)
}

/// XOR of all bytes (Viewlink serial frames).
#[must_use]
pub fn xor8(data: &[u8]) -> u8 {
    data.iter().fold(0, |acc, b| acc ^ b)
}

/// Sum of all bytes modulo 256 (Viewlink TCP envelope).
#[must_use]
pub fn sum8(data: &[u8]) -> u8 {
    data.iter().fold(0u8, |acc, b| acc.wrapping_add(*b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_check_values() {
        assert_eq!(crc16_mcrf4xx(b"123456789"), 0x6F91);
        assert_eq!(crc16_xmodem(b"123456789"), 0x31C3);
        assert_eq!(xor8(&[0x01, 0x02, 0x04]), 0x07);
        assert_eq!(sum8(&[0xFF, 0x02]), 0x01);
    }

    #[test]
    fn mcrf4xx_matches_the_k40t_document_algorithm() {
        // The C code of the K40T document, transcribed.
        fn doc_crc(data: &[u8]) -> u16 {
            let mut acc: u16 = 0xFFFF;
            for &b in data {
                let mut tmp = b ^ (acc & 0xFF) as u8;
                tmp ^= tmp << 4;
                let t = u16::from(tmp);
                acc = (acc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4);
            }
            acc
        }
        for data in [&b"123456789"[..], &[], &[0xFD, 0x00, 0x42], &[0xAA; 300]] {
            assert_eq!(crc16_mcrf4xx(data), doc_crc(data));
        }
    }
}
