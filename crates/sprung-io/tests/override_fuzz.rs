//! A property of `--set KEY=VALUE` (and Python's `set=`): no key or value,
//! however deep, long or odd its bytes, panics or overflows the stack;
//! each is taken or refused with a message. A stack overflow aborts this
//! test's process, so it fails rather than passing quietly.

use std::path::Path;

use sprung_io::scene::{MAX_KEY_BYTES, MAX_KEY_PARTS, MAX_VALUE_DEPTH};
use sprung_io::{parse_scene_overridden, Disk, Override};

const ROPE: &str = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"rope\"\nrope = { particles = 4, length = 1.0 }\nmass = 0.1\n";

/// xorshift64*: the same cases on every run.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    /// Mostly short, now and then far past the limits.
    fn length(&mut self) -> usize {
        match self.below(10) {
            0 => 1000 + self.below(60_000) as usize,
            1 => 20 + self.below(200) as usize,
            _ => self.below(8) as usize,
        }
    }
}

/// A key part: a name a scene has, a word, an index, a quoted string.
fn part(random: &mut Random) -> String {
    const NAMES: [&str; 9] = [
        "sim",
        "body",
        "rope",
        "dt",
        "0",
        "gas",
        "nrt",
        "collider",
        "stiffness",
    ];
    match random.below(6) {
        0 => "\"a.b= \\\"\"".to_string(),
        1 => "é".to_string(),
        2 => String::new(),
        _ => NAMES[random.below(NAMES.len() as u64) as usize].to_string(),
    }
}

/// A value: a number, a word, quotes, brackets and braces nested to a
/// random depth, sometimes unbalanced.
fn value(random: &mut Random) -> String {
    let depth = random.length();
    let (open, close) = match random.below(4) {
        0 => ("[", "]"),
        1 => ("{a=", "}"),
        2 => ("[\"", "\"]"),
        _ => ("[[", "]"),
    };
    let inner = match random.below(5) {
        0 => "1e-4",
        1 => "rk4",
        2 => "\"x",
        3 => "",
        _ => "[1, 2, 3]",
    };
    format!(
        "{}{inner}{}",
        open.repeat(depth),
        close.repeat(random.below(depth as u64 + 1) as usize)
    )
}

#[test]
fn no_key_or_value_panics_or_overflows() {
    let mut random = Random(0x5EED_1234_ABCD_0042);
    let (mut taken, mut refused) = (0, 0);
    for case in 0..400 {
        let parts: Vec<String> = (0..random.length().max(1))
            .map(|_| part(&mut random))
            .collect();
        let argument = match random.below(4) {
            // Now and then a key the scene has, with a value it takes.
            0 => [
                "sim.dt=2e-3",
                "body.rope.mass=0.2",
                "sim.steps=4",
                "sim.integrator=rk4",
            ][random.below(4) as usize]
                .to_string(),
            _ => format!("{}={}", parts.join("."), value(&mut random)),
        };
        let outcome = std::panic::catch_unwind(|| {
            let parsed: Result<Override, _> = argument.parse();
            match parsed {
                Ok(o) => parse_scene_overridden(ROPE, Path::new("r.toml"), &[o], &Disk)
                    .map(|_| ())
                    .map_err(|e| e.to_string()),
                Err(e) => Err(e.to_string()),
            }
        });
        let shown: String = argument.chars().take(80).collect();
        match outcome {
            Err(_) => panic!("case {case} panicked: {shown}"),
            Ok(Ok(())) => taken += 1,
            Ok(Err(message)) => {
                assert!(!message.is_empty(), "case {case}: {shown}");
                refused += 1;
            }
        }
    }
    // Both outcomes occur: the cases reach the limits and stay within them.
    assert!(taken > 0 && refused > 0, "taken {taken}, refused {refused}");
}

#[test]
fn the_limits_are_exact() {
    let scene = |o: Override| parse_scene_overridden(ROPE, Path::new("r.toml"), &[o], &Disk);
    // MAX_KEY_PARTS parts are taken (an unknown key, refused as such), one
    // more is refused by the limit.
    let key = |n: usize| format!("sim.{}=1", vec!["a"; n - 1].join("."));
    let at = key(MAX_KEY_PARTS)
        .parse::<Override>()
        .expect("parts at the limit");
    assert!(!scene(at).unwrap_err().to_string().contains("dotted parts"));
    let past = key(MAX_KEY_PARTS + 1).parse::<Override>().unwrap_err();
    assert!(
        past.to_string().contains("more than the 32 dotted parts"),
        "{past}"
    );
    let long = format!("sim.{}=1", "a".repeat(MAX_KEY_BYTES));
    let past = long.parse::<Override>().unwrap_err();
    assert!(
        past.to_string()
            .contains("more than the 4096 a key may have"),
        "{past}"
    );
    // A gravity nested MAX_VALUE_DEPTH deep is read (and refused as not a
    // vector); one level more is refused by the limit.
    let nested = |n: usize| format!("sim.gravity={}0{}", "[".repeat(n), "]".repeat(n));
    let at = nested(MAX_VALUE_DEPTH)
        .parse::<Override>()
        .expect("depth at the limit");
    assert!(!scene(at).unwrap_err().to_string().contains("deep"));
    let past = nested(MAX_VALUE_DEPTH + 1).parse::<Override>().unwrap_err();
    assert!(past.to_string().contains("more than 32 deep"), "{past}");
}
