//! Parsers of command-line values, so that a malformed value is a usage
//! error (exit status 2, with clap's message naming the option) before
//! anything runs, like an unparsable one.

use std::ffi::OsStr;

use clap::builder::TypedValueParser;
use sprung_io::scene::MAX_STEPS;
use sprung_io::Override;
use sprung_view::plot;
use sprung_view::render::{MAX_SIZE, MIN_SIZE};

/// A step count: 1 to [`MAX_STEPS`], the limit of the scene key `steps`.
pub fn steps(text: &str) -> Result<u64, String> {
    let n: u64 = text
        .parse()
        .map_err(|_| format!("`{text}` is not a whole number of steps"))?;
    if n == 0 || n > MAX_STEPS {
        return Err(format!("{n} steps: from 1 to {MAX_STEPS:.0e}"));
    }
    Ok(n)
}

/// A count of at least 1 (`--every`).
pub fn at_least_one(text: &str) -> Result<u64, String> {
    match text.parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err(format!("`{text}` is not a whole number")),
    }
}

/// A positive, finite number (a time in s, a rate, a strain, a margin).
pub fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(x) => Err(format!("{x}: must be positive and finite")),
        Err(_) => Err(format!("`{text}` is not a number")),
    }
}

/// A field of view strictly between 0 and 180 degrees.
pub fn field_of_view(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x < 180.0 => Ok(x),
        Ok(x) => Err(format!("{x}: must be between 0 and 180 degrees")),
        Err(_) => Err(format!("`{text}` is not a number")),
    }
}

/// A picture side of [`MIN_SIZE`] to [`MAX_SIZE`] pixels (`render`).
pub fn picture_side(text: &str) -> Result<u32, String> {
    side_within(text, MIN_SIZE, MAX_SIZE)
}

/// A plot side of [`plot::MIN_SIZE`] to [`plot::MAX_SIZE`] pixels (`plot`).
pub fn plot_side(text: &str) -> Result<u32, String> {
    side_within(text, plot::MIN_SIZE, plot::MAX_SIZE)
}

/// A whole number of pixels from `least` to `most`.
fn side_within(text: &str, least: u32, most: u32) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if (least..=most).contains(&n) => Ok(n),
        Ok(n) => Err(format!("{n} pixels: from {least} to {most}")),
        Err(_) => Err(format!("`{text}` is not a whole number of pixels")),
    }
}

/// The parser of `--set KEY=VALUE`: an override ([`Override`]'s own
/// parser), refused with the first byte that is not UTF-8 where the
/// argument is not text (arguments are bytes: no panic on any of them).
#[derive(Debug, Clone, Copy)]
pub struct OverrideArg;

impl TypedValueParser for OverrideArg {
    type Value = Override;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        _arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<Override, clap::Error> {
        let bytes = value.as_encoded_bytes();
        if let Err(e) = std::str::from_utf8(bytes) {
            let at = e.valid_up_to();
            let message = format!(
                "invalid value for '--set <KEY=VALUE>': byte {} (0x{:02x}) of `{}` is not UTF-8; a key and its value are text\n",
                at + 1,
                bytes[at],
                value.to_string_lossy()
            );
            return Err(
                clap::Error::raw(clap::error::ErrorKind::InvalidUtf8, message).with_cmd(cmd),
            );
        }
        let text = value.to_string_lossy();
        text.parse::<Override>().map_err(|e| {
            let message = format!("invalid value '{text}' for '--set <KEY=VALUE>': {e}\n");
            clap::Error::raw(clap::error::ErrorKind::ValueValidation, message).with_cmd(cmd)
        })
    }
}
