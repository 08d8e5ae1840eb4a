//! The viewer (`index.html`) driven in headless Chromium through the DevTools protocol: sliders,
//! pickers, wipe, FLIP overlay and the pixel readout reach the right cells and values, links
//! reproduce a view, and a 10 000-cell run opens quickly. A small CDP client over tungstenite.

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};

use serde_json::{json, Value};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

struct Browser {
    child: Child,
    ws: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
    session: String,
    /// Console errors, uncaught exceptions and failed loads the page reported.
    errors: Vec<String>,
    _profile: tempfile::TempDir,
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Browser {
    fn launch(binary: &str) -> Browser {
        let profile = tempfile::tempdir().unwrap();
        let mut child = Command::new(binary)
            .args(crate::common::chromium_flags(profile.path()))
            .args(["--remote-debugging-port=0", "--window-size=1400,1000"])
            .arg("about:blank")
            .stderr(Stdio::piped())
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let url = loop {
            let line = lines.next().expect("Chromium exited before its DevTools endpoint").unwrap();
            if let Some(u) = line.strip_prefix("DevTools listening on ") {
                break u.trim().to_string();
            }
        };
        // Keep draining stderr so Chromium never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        let (ws, _) = tungstenite::connect(url.as_str()).unwrap();
        let mut b = Browser { child, ws, next_id: 0, session: String::new(), errors: Vec::new(), _profile: profile };
        let target = b.call("Target.createTarget", json!({ "url": "about:blank" }))["targetId"].clone();
        let attached = b.call("Target.attachToTarget", json!({ "targetId": target, "flatten": true }));
        b.session = attached["sessionId"].as_str().unwrap().to_string();
        for domain in ["Page.enable", "Runtime.enable", "Log.enable"] {
            b.call(domain, json!({}));
        }
        b
    }

    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut msg = json!({ "id": id, "method": method, "params": params });
        if !self.session.is_empty() {
            msg["sessionId"] = json!(self.session);
        }
        self.ws.send(Message::text(msg.to_string())).unwrap();
        loop {
            let text = match self.ws.read().unwrap() {
                Message::Text(t) => t.to_string(),
                _ => continue,
            };
            let v: Value = serde_json::from_str(&text).unwrap();
            if v["id"].as_u64() == Some(id) {
                assert!(v.get("error").is_none(), "{method}: {v}");
                return v["result"].clone();
            }
            self.event(&v);
        }
    }

    fn event(&mut self, v: &Value) {
        match v["method"].as_str() {
            Some("Runtime.exceptionThrown") => self.errors.push(v["params"]["exceptionDetails"].to_string()),
            Some("Runtime.consoleAPICalled") if v["params"]["type"] == "error" => {
                self.errors.push(v["params"]["args"].to_string())
            }
            Some("Log.entryAdded") if v["params"]["entry"]["level"] == "error" => {
                self.errors.push(format!("{} {}", v["params"]["entry"]["text"], v["params"]["entry"]["url"]))
            }
            _ => {}
        }
    }

    /// The value of `expression` (awaited when a promise).
    fn eval(&mut self, expression: &str) -> Value {
        let r = self
            .call("Runtime.evaluate", json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }));
        assert!(r.get("exceptionDetails").is_none(), "{expression}: {r}");
        r["result"]["value"].clone()
    }

    /// Poll `expression` until it is true (10 s at most).
    fn wait_for(&mut self, expression: &str) {
        for _ in 0..200 {
            if self.eval(expression) == json!(true) {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        panic!("timed out waiting for {expression}");
    }

    fn open(&mut self, url: &str) {
        self.call("Page.navigate", json!({ "url": url }));
        self.wait_for("document.readyState === 'complete' && document.body && document.body.dataset.ready === '1'");
    }
}

fn file_url(path: &Path) -> String {
    format!("file://{}", path.display())
}

/// Set a control's value and fire `input`, as a person moving it does.
fn set(b: &mut Browser, id: &str, value: &str) {
    b.eval(&format!(
        "(function(){{var e=document.getElementById('{id}'); e.value='{value}'; e.dispatchEvent(new Event('input', {{bubbles:true}})); return true;}})()"
    ));
}

fn shown(b: &mut Browser) -> (String, String) {
    let v =
        b.eval("[document.getElementById('stage-wrap').dataset.a, document.getElementById('stage-wrap').dataset.b]");
    (v[0].as_str().unwrap().to_string(), v[1].as_str().unwrap().to_string())
}

fn img_srcs(b: &mut Browser) -> Vec<String> {
    let v = b.eval("Array.from(document.querySelectorAll('#stage-wrap img')).map(function(i){return decodeURIComponent(i.getAttribute('src'));})");
    v.as_array().unwrap().iter().map(|s| s.as_str().unwrap().to_string()).collect()
}

const MATRIX: &str = "name = \"viewer\"\ncompositions = [\"default\", \"my_room.toml\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lit\", \"standard\"]\npresets = [\"gold\", \"plastic\"]\nreference = { pipeline = \"hdrp\", shader = \"lit\" }\n[sweep]\nsmoothness = [0.2, 0.8]\n[image]\nwidth = 40\nheight = 32\n";

#[test]
fn the_viewer_follows_sliders_pickers_wipe_overlay_and_reads_pixels() {
    let _timer = crate::common::timed!();
    let Some(binary) = crate::common::chromium() else { return };
    let tmp = tempfile::tempdir().unwrap();
    // A user scene beside the built-in one: the viewer offers every composition of the run.
    let default = std::fs::read_to_string(crate::common::repo().join("scenes/default.toml")).unwrap();
    let mine = default.replacen("name = \"default\"", "name = \"my_room\"", 1);
    assert_ne!(mine, default, "the scene names itself");
    std::fs::write(tmp.path().join("my_room.toml"), mine).unwrap();
    let run = crate::common::run_matrix(tmp.path(), MATRIX, "run");
    for f in ["index.html", "viewer-data.js", "gallery.html"] {
        assert!(run.join(f).is_file(), "{f}");
    }
    let id = |pipeline: &str, preset: &str, s: &str| {
        let m = if preset == "gold" { "1.00" } else { "0.00" };
        format!("default__{pipeline}-forward__lit__{preset}__m{m}_s{s}_i2_r10")
    };
    for p in ["urp", "hdrp"] {
        assert!(run.join("cells").join(id(p, "gold", "0.20")).is_dir(), "{}", id(p, "gold", "0.20"));
    }
    let mut b = Browser::launch(&binary);
    b.open(&file_url(&run.join("index.html")));

    // A opens on the first cell; B is A in the other pipeline.
    assert_eq!(shown(&mut b), (id("hdrp", "gold", "0.20"), id("urp", "gold", "0.20")));
    // Side by side: both images.
    let srcs = img_srcs(&mut b);
    assert!(srcs.contains(&format!("cells/{}/image.png", id("hdrp", "gold", "0.20"))), "{srcs:?}");
    assert!(srcs.contains(&format!("cells/{}/image.png", id("urp", "gold", "0.20"))), "{srcs:?}");

    // The composition picker lists the user scene beside the built-in one, and picking it shows
    // its cell.
    let compositions =
        b.eval("Array.from(document.getElementById('a-composition').options).map(function(o){return o.textContent;})");
    assert_eq!(compositions, json!(["default", "my_room"]));
    set(&mut b, "a-composition", "1");
    assert!(shown(&mut b).0.starts_with("my_room__hdrp-forward__lit__gold"), "{:?}", shown(&mut b));
    set(&mut b, "a-composition", "0");
    assert_eq!(shown(&mut b), (id("hdrp", "gold", "0.20"), id("urp", "gold", "0.20")));

    // Moving A's smoothness slider moves B with it (B follows A's sliders) and shows the exact value.
    set(&mut b, "a-smoothness", "1");
    assert_eq!(shown(&mut b), (id("hdrp", "gold", "0.80"), id("urp", "gold", "0.80")));
    assert_eq!(b.eval("document.querySelector('#a-smoothness + output').textContent"), json!("0.8"));

    // A to URP, B to HDRP: B is then A's reference, and A has FLIP/SSIM maps.
    let urp = b.eval("Array.from(document.getElementById('a-pipeline').options).findIndex(function(o){return o.textContent==='urp';})");
    let hdrp = b.eval("Array.from(document.getElementById('b-pipeline').options).findIndex(function(o){return o.textContent==='hdrp';})");
    set(&mut b, "a-pipeline", &urp.to_string());
    set(&mut b, "b-pipeline", &hdrp.to_string());
    let (a, bb) = (id("urp", "gold", "0.80"), id("hdrp", "gold", "0.80"));
    assert_eq!(shown(&mut b), (a.clone(), bb.clone()));

    // The record beside: axes, metrics, timings (CPU wall, GPU per pass) and the frame plan.
    let record_text = b.eval("document.getElementById('record').textContent").as_str().unwrap().to_string();
    for part in ["smoothness = 0.8", "FLIP", "CPU wall median", "GPU per pass: ", "passes: "] {
        assert!(record_text.contains(part), "{part} missing from the record:\n{record_text}");
    }

    // The wipe: B's image clipped over A's, with a divider.
    b.eval("document.getElementById('mode-wipe').click(), true");
    assert_eq!(b.eval("!!document.getElementById('divider')"), json!(true));
    assert_eq!(
        b.eval("decodeURIComponent(document.getElementById('wipe-b').getAttribute('src'))"),
        json!(format!("cells/{bb}/image.png"))
    );

    // The FLIP overlay: A's map against its reference, at the chosen opacity.
    set(&mut b, "overlay", "flip");
    set(&mut b, "opacity", "0.35");
    let over = b.eval("(function(){var o=document.querySelector('#stage-wrap img.over'); return o ? [decodeURIComponent(o.getAttribute('src')), o.style.opacity] : null;})()");
    assert_eq!(over, json!([format!("cells/{a}/flip.png"), "0.35"]));
    let record: shadematrix::record::CellRecord =
        serde_json::from_str(&std::fs::read_to_string(run.join("cells").join(&a).join("cell.json")).unwrap()).unwrap();
    assert!(record.metrics.maps.is_some());

    // SSIM of A against B, computed in the page: the value compare::ssim gives for the two PNGs.
    set(&mut b, "overlay", "ssim_ab");
    b.wait_for("!!document.getElementById('pair').dataset.ssim");
    let page_ssim: f64 = b.eval("+document.getElementById('pair').dataset.ssim").as_f64().unwrap();
    let luma = |id: &str| {
        let png = image::open(run.join("cells").join(id).join("image.png")).unwrap().to_rgba8();
        shadematrix::compare::ssim::luma(png.as_raw())
    };
    let want = shadematrix::compare::ssim::ssim(&luma(&a), &luma(&bb), 40, 32).unwrap().mean;
    assert!((page_ssim - want).abs() < 1e-12, "page {page_ssim} vs compare::ssim {want}");
    assert!(page_ssim < 0.999, "URP and HDRP differ: {page_ssim}");
    // LDR-FLIP of A against B, computed in the page: within 1e-4 of flip-rs's (which works in f32).
    set(&mut b, "overlay", "flip_ab");
    b.wait_for("!!document.getElementById('pair').dataset.flip");
    let page_flip: f64 = b.eval("+document.getElementById('pair').dataset.flip").as_f64().unwrap();
    let rgba = |id: &str| image::open(run.join("cells").join(id).join("image.png")).unwrap().to_rgba8().into_raw();
    let want = shadematrix::compare::flip::ldr(&rgba(&bb), &rgba(&a), 40, 32).unwrap().mean;
    eprintln!("FLIP of A against B: page {page_flip}, flip-rs {want}");
    assert!((page_flip - want).abs() < 1e-4, "page {page_flip} vs flip-rs {want}");
    assert!(page_flip > 0.01, "URP and HDRP differ: {page_flip}");
    set(&mut b, "overlay", "flip");

    // The readout: hover pixel (13, 7) of A; the page reports A's PNG byte and EXR value there.
    let (x, y) = (13u32, 7u32);
    b.eval(&format!(
        "(function(){{var s=document.querySelector('#stage-wrap .stage'); var r=s.getBoundingClientRect(); var z=+document.getElementById('zoom').value; s.dispatchEvent(new MouseEvent('mousemove', {{clientX: r.left + ({x} + 0.5) * z, clientY: r.top + ({y} + 0.5) * z, bubbles: true}})); return true;}})()"
    ));
    b.wait_for(&format!(
        "document.getElementById('readout').dataset.px === '{x},{y}' && !!document.getElementById('readout').dataset.aLinear"
    ));
    let png = image::open(run.join("cells").join(&a).join("image.png")).unwrap().to_rgba8();
    let p = png.get_pixel(x, y);
    assert_eq!(
        b.eval("document.getElementById('readout').dataset.aSrgb"),
        json!(format!("{},{},{}", p[0], p[1], p[2]))
    );
    let linear: Vec<f64> = b
        .eval("document.getElementById('readout').dataset.aLinear")
        .as_str()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    use shadematrix::compare::images::LoadedImage;
    let LoadedImage::Hdr { width, rgba, .. } =
        LoadedImage::load(&run.join("cells").join(&a).join("image.exr")).unwrap()
    else {
        panic!("EXR")
    };
    let at = 4 * (y as usize * width as usize + x as usize);
    let want = [rgba[at], rgba[at + 1], rgba[at + 2]];
    for c in 0..3 {
        assert_eq!(linear[c], want[c] as f64, "channel {c}: the readout is the EXR's value");
    }
    let b_srgb = b.eval("document.getElementById('readout').dataset.bSrgb");
    let pb = image::open(run.join("cells").join(&bb).join("image.png")).unwrap().to_rgba8();
    let q = pb.get_pixel(x, y);
    assert_eq!(b_srgb, json!(format!("{},{},{}", q[0], q[1], q[2])));

    // The fragment holds the view: a new page on the same URL shows the same cells and modes.
    let url = b.eval("location.href").as_str().unwrap().to_string();
    assert!(url.contains("mode=wipe") && url.contains("overlay=flip") && url.contains("px=13,7"), "{url}");
    b.call("Page.navigate", json!({ "url": "about:blank" }));
    b.wait_for("location.href === 'about:blank' && document.readyState === 'complete'");
    b.open(&url);
    assert_eq!(shown(&mut b), (a.clone(), bb.clone()));
    assert_eq!(
        b.eval("!!document.getElementById('divider') && document.getElementById('overlay').value"),
        json!("flip")
    );

    // A pruned combination says why: Standard is the built-in pipeline's shader.
    let standard = b.eval("Array.from(document.getElementById('a-shader').options).findIndex(function(o){return o.textContent==='standard';})");
    set(&mut b, "a-shader", &standard.to_string());
    let why = b.eval("document.getElementById('why-a').textContent").as_str().unwrap().to_string();
    assert!(why.contains("pruned") && why.contains("not a shader of the urp pipeline"), "{why}");
    assert_eq!(shown(&mut b).0, "");
    assert_eq!(b.eval("document.body.dataset.errors"), json!("0"));
    assert!(b.errors.is_empty(), "console errors: {:?}", b.errors);
}

#[test]
fn a_ten_thousand_cell_run_opens_in_under_two_seconds() {
    let _timer = crate::common::timed!();
    let Some(binary) = crate::common::chromium() else { return };
    use shadematrix::report::viewer::{
        data_script, page, ViewerAxis, ViewerCell, ViewerData, ViewerRun, ViewerTiming, DATA_FILE,
    };
    let tmp = tempfile::tempdir().unwrap();
    // 4 compositions × 3 pipelines × 5 shaders × 12 presets × 14 smoothness = 10 080 cells.
    let names = |prefix: &str, n: usize| (0..n).map(|i| format!("{prefix}{i}")).collect::<Vec<_>>();
    let axes = vec![
        ("composition", "choice", names("comp", 4)),
        ("pipeline", "choice", names("pipe", 3)),
        ("shader", "choice", names("shader", 5)),
        ("preset", "choice", names("preset", 12)),
        ("smoothness", "number", (0..14).map(|i| format!("{}", i as f64 / 13.0)).collect()),
    ];
    let mut cells = Vec::new();
    for c in 0..4u32 {
        for p in 0..3u32 {
            for s in 0..5u32 {
                for r in 0..12u32 {
                    for m in 0..14u32 {
                        let id = format!("comp{c}__pipe{p}__shader{s}__preset{r}__s{m}");
                        cells.push(ViewerCell(
                            id,
                            vec![c, p, s, r, m],
                            -1,
                            -1,
                            [Some(0.1), Some(0.9), None],
                            Some(1.0),
                            0,
                            0,
                            [8, 8],
                            None,
                            ViewerTiming(Some(1.2), -1, vec![(0, 1.0)]),
                        ));
                    }
                }
            }
        }
    }
    assert_eq!(cells.len(), 10_080);
    // The two cells the page opens on have images; the rest are never requested.
    let png = image::RgbaImage::from_pixel(8, 8, image::Rgba([200, 100, 50, 255]));
    for id in [&cells[0].0, &cells[14 * 12 * 5].0] {
        std::fs::create_dir_all(tmp.path().join("cells").join(id)).unwrap();
        png.save(tmp.path().join("cells").join(id).join("image.png")).unwrap();
    }
    let data = ViewerData {
        schema: shadematrix::report::viewer::VIEWER_SCHEMA,
        run: ViewerRun {
            name: "synthetic".into(),
            adapter: "none".into(),
            matrix: "synthetic.toml".into(),
            status: "complete".into(),
            cells: cells.len(),
            rendered: cells.len(),
            twins: 0,
            pruned: 0,
        },
        axes: axes.into_iter().map(|(n, k, values)| ViewerAxis { name: n.into(), kind: k, values }).collect(),
        cells,
        plans: vec![vec!["forward".into()]],
        pass_kinds: vec!["forward".into()],
        pruned: Vec::new(),
        links: Vec::new(),
        flip: shadematrix::report::viewer::ViewerFlip::new(),
        terms: Vec::new(),
    };
    std::fs::write(tmp.path().join(DATA_FILE), data_script(&data).unwrap()).unwrap();
    std::fs::write(tmp.path().join("index.html"), page("synthetic").unwrap()).unwrap();
    let mut b = Browser::launch(&binary);
    b.open(&file_url(&tmp.path().join("index.html")));
    let ms: f64 = b.eval("+document.body.dataset.loadMs").as_f64().unwrap();
    eprintln!("10 080-cell viewer ready {ms:.0} ms after navigation");
    assert!(ms < 2000.0, "the viewer took {ms} ms to open 10 080 cells");
    // It still resolves a slider move.
    set(&mut b, "a-smoothness", "13");
    assert_eq!(shown(&mut b).0, "comp0__pipe0__shader0__preset0__s13");
    assert!(b.errors.iter().all(|e| e.contains("s13/image.png")), "console errors: {:?}", b.errors);
}

/// A run with term layers offers them: the *show* picker lists every layer, picking one shows
/// each cell's layer PNG in its stage, and the choice travels in the URL fragment.
#[test]
fn the_viewer_shows_a_cells_term_layers() {
    let _timer = crate::common::timed!();
    let Some(binary) = crate::common::chromium() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"viewer_terms\"\ncompositions = [\"default\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\n[outputs]\nterms = true\n[image]\nwidth = 32\nheight = 32\n";
    let run = crate::common::run_matrix(tmp.path(), body, "run");
    let mut b = Browser::launch(&binary);
    b.open(&file_url(&run.join("index.html")));
    assert_eq!(b.eval("document.getElementById('term-bar').hidden"), json!(false));
    let options = b.eval("Array.from(document.getElementById('term').options).map(function(o){return o.value;})");
    for layer in ["image", "direct_diffuse", "direct_specular", "indirect_specular", "occlusion"] {
        assert!(options.as_array().unwrap().contains(&json!(layer)), "{options}");
    }
    assert!(img_srcs(&mut b).iter().all(|s| s.ends_with("/image.png")), "{:?}", img_srcs(&mut b));
    set(&mut b, "term", "direct_specular");
    let srcs = img_srcs(&mut b);
    assert!(!srcs.is_empty() && srcs.iter().all(|s| s.ends_with("/terms/direct_specular.png")), "{srcs:?}");
    for s in &srcs {
        assert!(run.join(s).is_file(), "{s}");
    }
    let hash = b.eval("location.hash");
    assert!(hash.as_str().unwrap().contains("term=direct_specular"), "{hash}");
    assert!(b.errors.is_empty(), "{:?}", b.errors);
}

#[test]
fn b_can_be_a_cells_own_truth_with_its_noise_for_wipe_and_flicker() {
    let _timer = crate::common::timed!();
    let Some(binary) = crate::common::chromium() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"viewer_truth\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\nreference = { truth = \"physical\", spp = 4, noise = 0.0, bounces = 1 }\n[image]\nwidth = 32\nheight = 32\n";
    let run = crate::common::run_matrix(tmp.path(), body, "run");
    let mut b = Browser::launch(&binary);
    b.open(&file_url(&run.join("index.html")));
    let (a, _) = shown(&mut b);
    b.eval("(function(){var e=document.getElementById('bref'); e.checked=true; e.dispatchEvent(new Event('change')); return true;})()");
    assert_eq!(shown(&mut b), (a.clone(), format!("reference:{a}")));
    let srcs = img_srcs(&mut b);
    assert!(srcs.iter().any(|s| s.ends_with(&format!("{a}/reference.png"))), "{srcs:?}");
    for s in &srcs {
        assert!(run.join(s).is_file(), "{s}");
    }
    // The wipe puts the truth over A; flicker shows it alone as B.
    b.eval("document.getElementById('mode-wipe').click()");
    assert!(img_srcs(&mut b).iter().any(|s| s.ends_with("/reference.png")));
    b.eval("document.getElementById('mode-flicker').click()");
    b.eval("document.getElementById('mode-flicker').click()");
    let srcs = img_srcs(&mut b);
    assert!(srcs.len() == 1 && srcs[0].ends_with("/reference.png"), "{srcs:?}");
    // The truth's noise, over it: a picture the cell folder holds, and a link keeps the view.
    set(&mut b, "overlay", "noise");
    let srcs = img_srcs(&mut b);
    assert!(srcs.iter().any(|s| s.ends_with("/truth_noise.png")), "{srcs:?}");
    assert!(run.join("cells").join(&a).join("truth_noise.png").is_file());
    let hash = b.eval("location.hash").as_str().unwrap().to_string();
    assert!(hash.contains("bref=1") && hash.contains("overlay=noise"), "{hash}");
    b.open(&format!("{}{hash}", file_url(&run.join("index.html"))));
    assert_eq!(shown(&mut b), (a.clone(), format!("reference:{a}")));
    assert!(b.errors.is_empty(), "{:?}", b.errors);
}
