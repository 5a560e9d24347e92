//! A minimal PNG encoder: 8-bit grayscale, no compression (zlib "stored"
//! deflate blocks), so the lab needs no image dependency. Formatting only.
//!
//! Layout (PNG 1.2 / RFC 2083, zlib RFC 1950, deflate RFC 1951): the 8-byte
//! signature, then the chunks IHDR, IDAT and IEND, each `length | type | data |
//! CRC-32(type | data)`. The IDAT data is one zlib stream: header `78 01`,
//! stored blocks of at most 65535 bytes (`BFINAL` bit, `LEN`, `!LEN`, bytes),
//! then the Adler-32 of the raw image data, where every row is prefixed by its
//! filter type 0 (none).

/// The eight bytes every PNG file starts with.
pub const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Largest payload of one stored deflate block.
const STORED_MAX: usize = 65_535;

/// CRC-32 (ISO 3309, reflected polynomial `0xEDB88320`) as PNG chunks use it.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

/// Adler-32 (RFC 1950) of `bytes`.
pub fn adler32(bytes: &[u8]) -> u32 {
    const MOD: u32 = 65_521;
    let (mut a, mut b) = (1u32, 0u32);
    // 5552 bytes keep `b` below 2^32 before the reduction.
    for block in bytes.chunks(5552) {
        for &x in block {
            a += u32::from(x);
            b += a;
        }
        a %= MOD;
        b %= MOD;
    }
    (b << 16) | a
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    let len = u32::try_from(data.len()).expect("PNG chunk below 2^31 bytes");
    out.extend_from_slice(&len.to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// An 8-bit grayscale PNG of `width × height` pixels from `pixels` (row-major,
/// top row first, `width·height` bytes; 0 black, 255 white).
///
/// # Panics
/// If `pixels.len() != width·height`, or a side is 0 or above 2^31 − 1.
pub fn grayscale(width: usize, height: usize, pixels: &[u8]) -> Vec<u8> {
    assert_eq!(pixels.len(), width * height, "pixel count");
    let side = |v: usize| {
        assert!(v > 0 && v < (1 << 31), "PNG side out of range");
        u32::try_from(v).expect("checked above")
    };
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&side(width).to_be_bytes());
    ihdr.extend_from_slice(&side(height).to_be_bytes());
    // Bit depth 8, colour type 0 (grayscale), deflate, adaptive filtering
    // (every row uses filter 0), no interlace.
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);

    let mut raw = Vec::with_capacity((width + 1) * height);
    for row in pixels.chunks_exact(width) {
        raw.push(0);
        raw.extend_from_slice(row);
    }
    let blocks = raw.len().div_ceil(STORED_MAX).max(1);
    let mut z = Vec::with_capacity(raw.len() + 5 * blocks + 6);
    z.extend_from_slice(&[0x78, 0x01]);
    for (i, block) in raw.chunks(STORED_MAX).enumerate() {
        z.push(u8::from(i + 1 == blocks));
        let len = u16::try_from(block.len()).expect("block of at most 65535 bytes");
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&(!len).to_le_bytes());
        z.extend_from_slice(block);
    }
    z.extend_from_slice(&adler32(&raw).to_be_bytes());

    let mut out = Vec::with_capacity(z.len() + 64);
    out.extend_from_slice(&SIGNATURE);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &z);
    chunk(&mut out, b"IEND", &[]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_known_values() {
        // The CRC of an empty IEND chunk is in every PNG file.
        assert_eq!(crc32(b"IEND"), 0xAE42_6082);
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
        assert_eq!(adler32(&[]), 1);
        // Long input exercises the modular reduction.
        let big = vec![255u8; 100_000];
        let (mut a, mut b) = (1u64, 0u64);
        for &x in &big {
            a = (a + u64::from(x)) % 65_521;
            b = (b + a) % 65_521;
        }
        assert_eq!(u64::from(adler32(&big)), (b << 16) | a);
    }

    /// Reads back the stored blocks (the only kind written here).
    fn inflate_stored(z: &[u8]) -> Vec<u8> {
        assert_eq!(&z[..2], &[0x78, 0x01]);
        assert_eq!((u16::from(z[0]) << 8 | u16::from(z[1])) % 31, 0);
        let mut i = 2;
        let mut out = Vec::new();
        loop {
            let last = z[i] & 1 == 1;
            assert_eq!(z[i] >> 1, 0, "stored block type");
            let len = usize::from(u16::from_le_bytes([z[i + 1], z[i + 2]]));
            let nlen = u16::from_le_bytes([z[i + 3], z[i + 4]]);
            assert_eq!(!nlen as usize, len);
            out.extend_from_slice(&z[i + 5..i + 5 + len]);
            i += 5 + len;
            if last {
                break;
            }
        }
        assert_eq!(&z[i..], &adler32(&out).to_be_bytes());
        out
    }

    #[test]
    fn image_round_trips() {
        // 300 × 250 needs two stored blocks.
        let (w, h) = (300, 250);
        let px: Vec<u8> = (0..w * h).map(|i| (i * 7 % 251) as u8).collect();
        let png = grayscale(w, h, &px);
        assert_eq!(&png[..8], &SIGNATURE);
        let mut i = 8;
        let mut kinds = Vec::new();
        let mut idat = Vec::new();
        while i < png.len() {
            let len = u32::from_be_bytes(png[i..i + 4].try_into().unwrap()) as usize;
            let kind = &png[i + 4..i + 8];
            let data = &png[i + 8..i + 8 + len];
            let crc = u32::from_be_bytes(png[i + 8 + len..i + 12 + len].try_into().unwrap());
            assert_eq!(crc, crc32(&png[i + 4..i + 8 + len]));
            if kind == b"IHDR" {
                assert_eq!(u32::from_be_bytes(data[0..4].try_into().unwrap()), 300);
                assert_eq!(u32::from_be_bytes(data[4..8].try_into().unwrap()), 250);
                assert_eq!(&data[8..], &[8, 0, 0, 0, 0]);
            }
            if kind == b"IDAT" {
                idat.extend_from_slice(data);
            }
            kinds.push(String::from_utf8(kind.to_vec()).unwrap());
            i += 12 + len;
        }
        assert_eq!(kinds, ["IHDR", "IDAT", "IEND"]);
        let raw = inflate_stored(&idat);
        assert_eq!(raw.len(), (w + 1) * h);
        for (r, row) in raw.chunks_exact(w + 1).enumerate() {
            assert_eq!(row[0], 0, "filter byte");
            assert_eq!(&row[1..], &px[r * w..(r + 1) * w]);
        }
    }
}
