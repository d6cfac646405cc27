//! The command line of `sprung-viewer` (and of `sprung view`, which passes
//! its arguments on).

use std::path::PathBuf;

/// Usage, printed by `--help` and after a malformed command line.
pub const USAGE: &str = "\
usage: sprung-viewer [SCENE.toml] [--demo NAME] [--frames N] [--screenshot FILE]
                     [--exit-after SECONDS] [--size WxH] [--device cpu|gpu|gpu_f64]

  SCENE.toml          a scene file (default: the demo ball2d; pick others in the window)
  --demo NAME         start on a built-in demo (ball2d, ball3d, flag, ...)
  --frames N          draw N frames, then exit (0, or 1 if the scene could not be loaded)
  --screenshot FILE   with --frames: save the last frame as a PNG
  --exit-after S      exit after S seconds of wall-clock time
  --size WxH          window size in pixels (default 1280x800)
  --device cpu|gpu|gpu_f64
                      where the steps run (default: the scene's `device`); on the
                      GPU (in f32, or f64) while it can run the world (not while a
                      hand holds it)";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// A scene file to open.
    pub scene: Option<PathBuf>,
    /// A demo to open, by name.
    pub demo: Option<String>,
    /// Draw this many frames, then exit.
    pub frames: Option<u64>,
    /// Save the last frame here (PNG).
    pub screenshot: Option<PathBuf>,
    /// Exit after this many seconds.
    pub exit_after: Option<f64>,
    /// Window size (pixels).
    pub size: (u32, u32),
    /// Where the steps run, instead of the scene's `device`.
    pub device: Option<sprung_io::Device>,
    /// Print the usage and exit.
    pub help: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scene: None,
            demo: None,
            frames: None,
            screenshot: None,
            exit_after: None,
            size: (1280, 800),
            device: None,
            help: false,
        }
    }
}

/// Parse the arguments after the program name.
pub fn parse(args: impl IntoIterator<Item = String>) -> Result<Options, String> {
    let mut options = Options::default();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let mut value = |flag: &str| args.next().ok_or_else(|| format!("`{flag}` needs a value"));
        match arg.as_str() {
            "-h" | "--help" => options.help = true,
            "--demo" => options.demo = Some(value("--demo")?),
            "--frames" => options.frames = Some(number(&value("--frames")?, "--frames")?),
            "--screenshot" => options.screenshot = Some(PathBuf::from(value("--screenshot")?)),
            "--exit-after" => {
                let seconds: f64 = number(&value("--exit-after")?, "--exit-after")?;
                if !(seconds.is_finite() && seconds >= 0.0) {
                    return Err(format!("`--exit-after {seconds}`: give seconds, 0 or more"));
                }
                options.exit_after = Some(seconds);
            }
            "--size" => options.size = size(&value("--size")?)?,
            "--device" => {
                let name = value("--device")?;
                let device = name
                    .parse()
                    .map_err(|e| format!("`--device {name}`: {e}"))?;
                options.device = Some(device);
            }
            flag if flag.starts_with('-') => return Err(format!("unknown option `{flag}`")),
            path if options.scene.is_none() => options.scene = Some(PathBuf::from(path)),
            extra => {
                return Err(format!(
                    "unexpected argument `{extra}` (one scene at a time)"
                ))
            }
        }
    }
    if options.scene.is_some() && options.demo.is_some() {
        return Err("give a scene file or `--demo NAME`, not both".into());
    }
    if options.screenshot.is_some() && options.frames.is_none() && options.exit_after.is_none() {
        return Err("`--screenshot` needs `--frames N` or `--exit-after S`".into());
    }
    Ok(options)
}

fn number<T: std::str::FromStr>(text: &str, flag: &str) -> Result<T, String> {
    text.parse()
        .map_err(|_| format!("`{flag} {text}`: not a valid number"))
}

fn size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`--size {text}`: give WIDTHxHEIGHT in pixels, e.g. 1280x800");
    let (w, h) = text.split_once('x').ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(200..=8192).contains(&w) || !(200..=8192).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(line: &str) -> Result<Options, String> {
        parse(line.split_whitespace().map(String::from))
    }

    #[test]
    fn scene_frames_and_screenshot() {
        let options = parse_str("a.toml --frames 30 --screenshot shot.png").unwrap_or_default();
        assert_eq!(options.scene, Some(PathBuf::from("a.toml")));
        assert_eq!(options.frames, Some(30));
        assert_eq!(options.screenshot, Some(PathBuf::from("shot.png")));
    }

    #[test]
    fn bad_lines_are_refused_with_the_flag_named() {
        for (line, words) in [
            ("--frames x", "--frames x"),
            ("--frames", "needs a value"),
            ("--bogus", "--bogus"),
            ("a.toml b.toml", "b.toml"),
            ("a.toml --demo flag", "not both"),
            ("--screenshot s.png", "--frames"),
            ("--size 10x10", "--size"),
            ("--exit-after -1", "--exit-after"),
        ] {
            let error = parse_str(line).err().unwrap_or_default();
            assert!(error.contains(words), "{line}: {error}");
        }
    }

    #[test]
    fn size_and_demo() {
        let options = parse_str("--demo flag --size 640x480").unwrap_or_default();
        assert_eq!(options.demo.as_deref(), Some("flag"));
        assert_eq!(options.size, (640, 480));
    }
}
