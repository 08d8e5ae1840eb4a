//! The offline gallery in headless Chromium (Debian `chromium`, installed by .ci/run): no script
//! errors, no broken images, a screenshot taken; and the check catches a broken image.

use std::path::Path;
use std::process::Command;

fn chromium_args(profile: &Path) -> Vec<String> {
    let mut flags = crate::common::chromium_flags(profile);
    flags.push("--virtual-time-budget=10000".into());
    flags
}

/// (images, broken images, script errors) as the page counted them after loading.
fn page_status(browser: &str, page: &Path, profile: &Path) -> (i64, i64, i64) {
    let out = Command::new(browser)
        .args(chromium_args(profile))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    let body = dom.split("<body").nth(1).and_then(|b| b.split('>').next()).unwrap_or_default().to_string();
    let attr = |name: &str| -> i64 {
        body.split(&format!("{name}=\""))
            .nth(1)
            .and_then(|v| v.split('"').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or(-99)
    };
    (attr("data-images"), attr("data-broken-images"), attr("data-errors"))
}

#[test]
fn gallery_loads_cleanly_in_headless_chromium() {
    let _timer = crate::common::timed!();
    let Some(browser) = crate::common::chromium() else { return };
    let tmp = tempfile::tempdir().unwrap();
    // The matrix file's name reaches the page (as the run's origin): it must arrive escaped.
    let m = crate::common::write_matrix(
        tmp.path(),
        "m&<x>.toml",
        "name = \"g\"\ncompositions = [\"default\", \"medusa\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"plastic\", \"gold\"]\nreference = { pipeline = \"hdrp\", shader = \"lit\" }\n[image]\nwidth = 48\nheight = 48\n",
    );
    let (rc, _, stderr) = crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "run"], &[]);
    assert_eq!(rc, 0, "{stderr}");
    let run = tmp.path().join("run");
    for p in [
        "index.html",
        "gallery.html",
        "viewer-data.js",
        "tables/perf.md",
        "tables/perf.csv",
        "tables/perf.json",
        "tables/error_vs_time.md",
        "plots/error_vs_time_default.svg",
        "plots/error_vs_time_medusa.svg",
    ] {
        assert!(run.join(p).is_file(), "{p}");
    }
    assert!(std::fs::read_dir(run.join("sheets")).unwrap().count() >= 2);
    let html = std::fs::read_to_string(run.join("gallery.html")).unwrap();
    assert!(html.contains("m&amp;&lt;x&gt;.toml") && !html.contains("m&<x>.toml"), "origin escaped");

    let profile = tmp.path().join("profile");
    let (images, broken, errors) = page_status(&browser, &run.join("gallery.html"), &profile);
    assert!(images > 16, "images on the page: {images}");
    assert_eq!((broken, errors), (0, 0), "broken images, script errors");
    let shot = tmp.path().join("gallery.png");
    let status = Command::new(&browser)
        .args(chromium_args(&profile))
        .arg(format!("--screenshot={}", shot.display()))
        .arg("--window-size=1400,1000")
        .arg(format!("file://{}", run.join("gallery.html").display()))
        .output()
        .unwrap();
    assert!(status.status.success());
    let png = image::open(&shot).unwrap();
    assert_eq!((png.width(), png.height()), (1400, 1000));

    // The check can fail: remove one cell's image and the page counts it broken.
    let cell = std::fs::read_dir(run.join("cells")).unwrap().next().unwrap().unwrap().path();
    std::fs::remove_file(cell.join("image.png")).unwrap();
    let (_, broken, _) = page_status(&browser, &run.join("gallery.html"), &profile);
    assert_eq!(broken, 1);
}
