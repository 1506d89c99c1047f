//! The public constructors that copy caller data into a value (text, byte blocks,
//! target lists) and validate ranges.

use core::hint::black_box;
use protocol_core::Text;
use protocol_core::siyi::{HardwareId, Product};
use protocol_core::viewlink::{AiTarget, AiTargets, Bytes, Date, TimeCs, Transparent};

pub fn exercise(input: &[u8], out: &mut [u8]) {
    if let Ok(s) = core::str::from_utf8(input) {
        black_box(Text::<20>::new(s).map(|t| t.as_str().map(str::len)));
        black_box(HardwareId::from_text(s));
        black_box(HardwareId::for_product(black_box(Product::Zt6), s));
    }
    black_box((Bytes::<60>::new(input), Transparent::new(input)));
    let b = black_box(0u8);
    black_box((Date::new(u16::from(b), b, b), TimeCs::new(b, b, b, b)));
    let targets = [black_box(AiTarget::default()); 5];
    let n = black_box(targets.len());
    black_box(AiTargets::new(
        b,
        b,
        b,
        targets.get(..n).unwrap_or_default(),
    ));
    black_box(out.len());
}
