//! Checksums written from the vendor documents, independently of `protocol-core`: the
//! tests build frames with these and check the codec against them.

/// The K40T document's `crc_calculate` (X25_INIT_CRC 0xFFFF, `crc_accumulate`),
/// transcribed. Equals CRC-16/MCRF4XX.
pub fn k40t_crc(data: &[u8]) -> u16 {
    let mut acc: u16 = 0xFFFF;
    for &b in data {
        let mut tmp = b ^ (acc & 0xFF) as u8;
        tmp ^= tmp << 4;
        let t = u16::from(tmp);
        acc = (acc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4);
    }
    acc
}

/// CRC-16/XMODEM bit by bit (poly 0x1021, init 0, no reflection, no final xor), as the
/// SIYI document specifies it.
pub fn xmodem_bitwise(data: &[u8]) -> u16 {
    let mut crc: u16 = 0;
    for &b in data {
        crc ^= u16::from(b) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// The GCU document's `CalculateCrc16` (nibble table, polynomial 0x1021, initial 0),
/// transcribed.
pub fn gcu_crc(data: &[u8]) -> u16 {
    const TABLE: [u16; 16] = [
        0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50a5, 0x60c6, 0x70e7, 0x8108, 0x9129, 0xa14a,
        0xb16b, 0xc18c, 0xd1ad, 0xe1ce, 0xf1ef,
    ];
    let mut crc: u16 = 0;
    for &b in data {
        let da = (crc >> 12) as u8;
        crc <<= 4;
        crc ^= TABLE[usize::from(da ^ (b >> 4))];
        let da = (crc >> 12) as u8;
        crc <<= 4;
        crc ^= TABLE[usize::from(da ^ (b & 0x0F))];
    }
    crc
}
