//! The book's LED table (docs/src/firmware/wiring.md, section "LED2") is the firmware's
//! (`bridge_fw::led::LED_CODES`): the same codes, in the same order, each with the same
//! "when" and the same pattern. On a difference the test prints the table as the code
//! has it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use bridge_fw::led::LED_CODES;

const WIRING: &str = include_str!("../../docs/src/firmware/wiring.md");

/// The rows of the first table after the heading `## LED2`: (code, when, pattern), the
/// pattern without its backticks.
fn book_rows() -> Vec<[String; 3]> {
    let section = WIRING
        .split("\n## ")
        .find(|s| s.starts_with("LED2"))
        .expect("a section `## LED2`");
    section
        .lines()
        .skip_while(|l| !l.starts_with("| code | when | pattern |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<String> = l
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().trim_matches('`').to_string())
                .collect();
            cells
                .try_into()
                .unwrap_or_else(|c| panic!("not three cells: {c:?}"))
        })
        .collect()
}

fn code_rows() -> Vec<[String; 3]> {
    LED_CODES
        .iter()
        .map(|c| {
            let mut pattern = String::new();
            c.describe(&mut pattern).unwrap();
            [c.name.to_string(), c.when.to_string(), pattern]
        })
        .collect()
}

#[test]
fn the_books_led_table_is_the_firmwares() {
    let (book, code) = (book_rows(), code_rows());
    let table: String = code
        .iter()
        .map(|[n, w, p]| format!("| {n} | {w} | `{p}` |\n"))
        .collect();
    assert!(
        book == code,
        "the book's LED table differs from the code's; the code's:\n{table}"
    );
}

/// The codes an integrator tells apart by eye: no two have the same pattern, and every
/// flash of the status cycle is at least 40 ms (shorter does not show on LED2).
#[test]
fn every_code_is_its_own_pattern() {
    let code = code_rows();
    for (i, a) in code.iter().enumerate() {
        for b in &code[i + 1..] {
            let status_slot = |r: &[String; 3]| r[1].starts_with("status cycle");
            // The three status flashes share long and short by design: their place in
            // the cycle tells them apart.
            if !(status_slot(a) && status_slot(b) && a[1] != b[1]) {
                assert_ne!(a[2], b[2], "{} and {}", a[0], b[0]);
            }
        }
    }
    for c in LED_CODES {
        assert!(c.steps().all(|s| !s.on || s.ms >= 40), "{}", c.name);
    }
}
