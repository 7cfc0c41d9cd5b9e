//! A PNG figure is written like every other output file (`preflight::save`): whole or not at
//! all, over a link rather than through it, and an error names the file.

use compare::plot::{Curve, Dash, Labels, line_chart};
use std::path::{Path, PathBuf};

const LABELS: Labels = Labels {
    title: "a figure",
    x: "x [m]",
    y: "y [-]",
};

fn curves() -> Vec<Curve> {
    let points = (0..50)
        .map(|i| (i as f64 * 0.1, (i as f64 * 0.3).sin()))
        .collect();
    vec![Curve::nth("sine", points, 0, Dash::Solid)]
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("figure-files-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// (width, height) of the PNG at `path`, which must decode whole.
fn decoded_size(path: &Path) -> (u32, u32) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    (info.width, info.height)
}

const CHILD: &str = "COMPARE_FIGURE_FILES_CHILD";

/// A disk that fills up while the figure is written (here the file-size limit of the process,
/// RLIMIT_FSIZE, at 4 KiB: a write past it fails with EFBIG, as on a full disk): the figure
/// written before stays whole, no temporary file is left, and the error names the file. The
/// limit is the whole process's, so the test runs the writing half in a child process of this
/// test binary.
#[test]
fn a_figure_whose_write_fails_half_way_leaves_the_previous_one_whole() {
    if let Ok(dir) = std::env::var(CHILD) {
        let path = Path::new(&dir).join("fig.png");
        let e = format!("{:#}", line_chart(&path, LABELS, &curves(), &[]).unwrap_err());
        assert!(e.contains(&path.display().to_string()), "{e}");
        println!("the error: {e}");
        return;
    }
    let dir = scratch("half-way");
    let path = dir.join("fig.png");
    std::fs::write(&path, b"the previous figure").unwrap();
    let mut child = std::process::Command::new(std::env::current_exe().unwrap());
    child
        .args([
            "a_figure_whose_write_fails_half_way_leaves_the_previous_one_whole",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, &dir);
    // SAFETY: between fork and exec, only async-signal-safe calls (setrlimit, signal)
    unsafe {
        std::os::unix::process::CommandExt::pre_exec(&mut child, || {
            let limit = libc::rlimit {
                rlim_cur: 4096,
                rlim_max: 4096,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // a write past the limit fails (EFBIG) instead of killing the process
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            Ok(())
        });
    }
    let out = child.output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("the error: "), "the child did not write: {text}");
    let now = std::fs::read(&path).unwrap();
    assert!(
        now == b"the previous figure",
        "the previous figure is gone ({} bytes now): {text}",
        now.len()
    );
    assert_eq!(listing(&dir), ["fig.png"], "a temporary file left");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A symbolic link at the figure's path is replaced by the figure; its target is untouched.
#[test]
fn a_link_at_a_figure_path_is_replaced_not_followed() {
    let dir = scratch("link");
    let target = dir.join("theirs.png");
    std::fs::write(&target, b"theirs").unwrap();
    let path = dir.join("fig.png");
    std::os::unix::fs::symlink(&target, &path).unwrap();
    line_chart(&path, LABELS, &curves(), &[]).unwrap();
    assert!(
        std::fs::read(&target).unwrap() == b"theirs",
        "written through the link"
    );
    assert!(!std::fs::symlink_metadata(&path).unwrap().is_symlink());
    assert_eq!(decoded_size(&path), (1000, 700));
    assert_eq!(listing(&dir), ["fig.png", "theirs.png"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A figure that cannot be written at all (its folder is a file) says which file.
#[test]
fn a_figure_that_cannot_be_written_names_its_file() {
    let dir = scratch("no-folder");
    let folder = dir.join("figures");
    std::fs::write(&folder, b"a file, not a folder").unwrap();
    let path = folder.join("fig.png");
    let e = format!("{:#}", line_chart(&path, LABELS, &curves(), &[]).unwrap_err());
    assert!(e.contains(&path.display().to_string()), "{e}");
    assert_eq!(listing(&dir), ["figures"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
