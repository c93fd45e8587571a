//! Levels kept while the eye stays in a ball (`render::level_ball`), on lavapipe with the
//! validation layer on: a frame whose eye is in the ball estimates only what comes into view,
//! its image keeps every pixel that shows the same triangle as `pixel` mode within ε, and a
//! frame whose eye has left the ball estimates again, as much as a renderer that never drew.

mod common;

use ash::vk;
use common::{assert_validation_clean, cracks, repo_path, validated_context};
use glam::Quat;
use multirate::analysis::metrics;
use multirate::gpu_interface::slots::{CAPPED_ESTIMATE_DISPATCH, FULL_ESTIMATE_DISPATCH, LEVEL_DISPATCHES};
use multirate::render::{Mode, Renderer, View};
use multirate::scene::{Camera, Scene};
use multirate::vk::target::{AfterPass, RenderTarget};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// How many triangles the range step sent to the estimator in the frame of `view` (every
/// mesh, both lists).
fn estimated(renderer: &Renderer, target: &RenderTarget, view: &View, meshes: usize) -> u32 {
    let dispatches = renderer.pre_pass_dispatches(target, view).expect("dispatches");
    let per_mesh = LEVEL_DISPATCHES as usize;
    (0..meshes)
        .map(|mesh| {
            let at = |slot: u32| dispatches[mesh * per_mesh + slot as usize][3];
            at(FULL_ESTIMATE_DISPATCH) + at(CAPPED_ESTIMATE_DISPATCH)
        })
        .sum()
}

/// `camera` turned about its target (about its up direction) so that its eye moves by `distance`.
fn turned(camera: Camera, distance: f32) -> Camera {
    let radius = camera.eye.distance(camera.target);
    let angle = 2.0 * (0.5 * distance / radius).asin();
    let eye =
        camera.target + Quat::from_axis_angle(camera.up.normalize(), angle) * (camera.eye - camera.target);
    Camera { eye, ..camera }
}

/// A validated context, a target of the tests' size and the scene `relative` at that size.
fn set_up(relative: &str) -> (std::sync::Arc<multirate::vk::Context>, RenderTarget, Scene) {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let mut scene = Scene::load(&repo_path(relative)).expect("scene");
    (scene.settings.width, scene.settings.height) = (WIDTH, HEIGHT);
    (context, target, scene)
}

/// A path of one second that turns the scene's camera until its eye has moved by 0.4 of its
/// distance to the target, at `fps` frames a second.
fn turn_path(scene: &Scene, fps: f32) -> multirate::render::PathFrames {
    use multirate::scene::path::{CameraPath, PathKey};
    let start = scene.camera;
    let end = turned(start, 0.4 * start.eye.distance(start.target));
    let key = |time: f32, camera: Camera| PathKey { time, eye: camera.eye, target: camera.target };
    let path = CameraPath::Keys(vec![key(0.0, start), key(1.0, end)]);
    multirate::render::PathFrames { path: std::sync::Arc::new(path), fps, start, bounds: scene.bounds() }
}

#[test]
fn levels_are_kept_while_the_eye_stays_in_its_ball() {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    for relative in ["scenes/teapot.toml", "scenes/bunny.toml"] {
        let mut scene = Scene::load(&repo_path(relative)).expect("scene");
        (scene.settings.width, scene.settings.height) = (WIDTH, HEIGHT);
        let meshes = scene.meshes.len();
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
        let radius = view.estimator.eye_radius;
        assert!(radius > 0.0, "{relative}: the default view keeps its levels in a ball");

        // The first frame begins the ball; the same view again estimates nothing.
        let first = estimated(&renderer, &target, &view, meshes);
        let again = estimated(&renderer, &target, &view, meshes);
        assert!(first > 0, "{relative}: the first frame estimates");
        assert_eq!(again, 0, "{relative}: the same eye keeps every level");

        // An eye 0.9 of the radius away stays in the ball: it estimates only what came into
        // view, and what it draws is within ε of `pixel` mode at that eye.
        let inside = View { camera: turned(view.camera, 0.9 * radius), ..view.clone() };
        let moved = estimated(&renderer, &target, &inside, meshes);
        assert!(
            2 * moved < first,
            "{relative}: {moved} estimated after a move within the ball, {first} first"
        );
        let within_epsilon = |at: &View| {
            let reference =
                renderer.analyze(&target, &View { mode: Mode::Pixel, ..at.clone() }).expect("pixel");
            let analysis = renderer.analyze(&target, at).expect("multirate");
            assert_eq!(cracks(&reference.image, &analysis.image), 0, "{relative}: cracks");
            let epsilon = f64::from(view.estimator.epsilon);
            let over = metrics::pixels_over(reference.frame(), analysis.frame(), epsilon);
            assert_eq!(over, 0, "{relative}: {over} pixels of the same triangle over ε with kept levels");
        };
        within_epsilon(&inside);

        // An eye twice the radius away has left the ball: it estimates again, at least what a
        // renderer that never drew estimates there (its ball, widened by the eye's step, leaves
        // the range class no more to settle than the configured one).
        let outside = View { camera: turned(view.camera, 2.0 * radius), ..view.clone() };
        let anew = estimated(&renderer, &target, &outside, meshes);
        let fresh = Renderer::new(&context, &scene).expect("renderer");
        let never_drew = estimated(&fresh, &target, &outside, meshes);
        assert!(
            anew >= never_drew && never_drew > moved,
            "{relative}: a new ball, {anew} against {never_drew}"
        );
        // That ball holds three more steps of the eye's latest (from `inside`): an eye as far
        // again along the turn stays in it, reuses the levels, and they hold there too.
        let further = View { camera: turned(view.camera, 4.0 * radius), ..view.clone() };
        let reused = estimated(&renderer, &target, &further, meshes);
        assert!(
            2 * reused < anew,
            "{relative}: {reused} estimated in the widened ball, {anew} when it began"
        );
        within_epsilon(&further);
        eprintln!(
            "{relative}: estimated {first} first, {again} again, {moved} moved within the ball, {anew} outside, \
             {reused} further on"
        );
    }
    assert_validation_clean(&context);
}

/// Records a frame of `view` into a command buffer that is never submitted, and drops it.
fn record_without_submitting(
    context: &multirate::vk::Context,
    renderer: &Renderer,
    target: &RenderTarget,
    view: &View,
) {
    let device = &context.device;
    let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(context.queue_family);
    // SAFETY: the pool and its buffer live only in this function; the buffer is never submitted.
    unsafe {
        let pool = device.create_command_pool(&pool_info, None).expect("pool");
        let allocate = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1);
        let cmd = device.allocate_command_buffers(&allocate).expect("command buffer")[0];
        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
        let _never_submitted = renderer.record(cmd, target, view, AfterPass::Readback);
        device.end_command_buffer(cmd).expect("end");
        device.destroy_command_pool(pool, None);
    }
}

/// Recording is pure: the ball moves only when a frame drawn for the image is submitted
/// (`Renderer::submitted`). Frames recorded and never submitted, and the analysis, counting and
/// level-recording frames, leave it where it was, and leave its kept levels holding for it,
/// wherever their eye is.
#[test]
fn only_submitted_frames_move_the_ball() {
    let (context, target, scene) = set_up("scenes/bunny.toml");
    let meshes = scene.meshes.len();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    let away = View { camera: turned(view.camera, 2.0 * view.estimator.eye_radius), ..view.clone() };
    let frames_that_commit_nothing = |at: &View| {
        renderer.prepare(at, &target).expect("prepare");
        record_without_submitting(&context, &renderer, &target, at);
        record_without_submitting(&context, &renderer, &target, at);
        renderer.analyze(&target, at).expect("analysis");
        renderer.count_evaluations(&target, at).expect("counts");
        renderer.record_levels(&target, at).expect("level records");
    };

    frames_that_commit_nothing(&away);
    assert_eq!(renderer.level_ball_centre(), None, "no frame was submitted for the image");
    assert!(estimated(&renderer, &target, &view, meshes) > 0, "so the first frame for the image estimates");
    assert_eq!(estimated(&renderer, &target, &view, meshes), 0, "and the next one reuses its levels");

    assert_eq!(renderer.level_ball_centre(), Some(view.camera.eye), "a frame for the image begins the ball");
    let before = renderer.analyze(&target, &view).expect("analysis").image;
    frames_that_commit_nothing(&away);
    assert_eq!(renderer.level_ball_centre(), Some(view.camera.eye), "the ball stays where it was");
    // Its kept levels were neither cleared nor replaced by the frames from outside it.
    let after = renderer.analyze(&target, &view).expect("analysis").image;
    assert!(before.pixels == after.pixels, "the frames from outside the ball changed the kept levels");
    assert_eq!(estimated(&renderer, &target, &view, meshes), 0, "the kept levels still hold");
    assert_validation_clean(&context);
}

/// Levels held between the balls (`render::level_hold`): along eyes that each leave the last
/// ball, so that every frame estimates every visible triangle, a renderer that holds its levels
/// uses exactly the levels the Rust twin holds from the estimates of one that does not, each at
/// least its estimate, so within ε; levels of two eyes taken in turns stop changing; and levels
/// a later eye finds coarser fall after a few estimates, not all in the same frame.
#[test]
fn levels_are_held_between_the_balls_as_the_twin_holds_them() {
    use multirate::gpu_types::LevelHold;
    use multirate::render::level_hold::held_level;
    use multirate::shading::estimator::uniform_level;

    let (context, target, scene) = set_up("scenes/bunny.toml");
    let holding = Renderer::new(&context, &scene).expect("renderer");
    let unheld = Renderer::new(&context, &scene).expect("renderer");
    let view = View { mode: Mode::Multirate, hold_levels: true, ..View::of_scene(&scene) };
    // Eyes 8 radii apart along a turn: farther than the widest ball (`level_ball::MOST_WIDENED`
    // radii) from the one before. Two eyes in turns, then two others in turns. The first frame's
    // ball has the configured radius, the others the widest (the eye moved): from the fourth
    // frame on, the first two eyes' estimates repeat.
    let step = 8.0 * view.estimator.eye_radius;
    let stops = [0, 1, 0, 1, 0, 1, 3, 4, 3, 4, 3, 4, 3, 4];
    let n_max = view.estimator.n_max;
    let mut twin = vec![LevelHold::default(); scene.triangle_count()];
    let (mut previous, mut fell): (Option<Vec<f32>>, Vec<usize>) = (None, Vec::new());
    for (frame, &stop) in stops.iter().enumerate() {
        let at = View { camera: turned(view.camera, stop as f32 * step), ..view.clone() };
        let levels = holding.pre_pass_levels(&target, &at).expect("held levels");
        let estimates =
            unheld.pre_pass_levels(&target, &View { hold_levels: false, ..at.clone() }).expect("levels");
        let mut visible = 0;
        for (t, (&level, &estimate)) in levels.iter().zip(&estimates).enumerate() {
            if estimate < 0.0 {
                assert_eq!(level, estimate, "frame {frame}: triangle {t} culled in one renderer only");
                continue;
            }
            visible += 1;
            let (expected, after) = held_level(t as u32, estimate, twin[t], n_max);
            twin[t] = after;
            assert_eq!(level, expected, "frame {frame}, triangle {t}: the pre-pass against the twin");
            assert!(level >= estimate, "frame {frame}, triangle {t}: {level} under its estimate {estimate}");
        }
        assert!(visible > 1000, "frame {frame}: {visible} visible triangles");
        if let Some(before) = &previous {
            let pattern = |level: f32| uniform_level(level, n_max);
            let changed = |a: &[f32], b: &[f32]| {
                a.iter()
                    .zip(b)
                    .filter(|(x, y)| **x >= 0.0 && **y >= 0.0 && pattern(**x) != pattern(**y))
                    .count()
            };
            if (3..6).contains(&frame) {
                assert_eq!(
                    changed(before, &levels),
                    0,
                    "frame {frame}: two eyes in turns change nothing held"
                );
            }
            fell.push(
                levels
                    .iter()
                    .zip(before)
                    .filter(|(now, was)| **now >= 0.0 && pattern(**now) < pattern(**was))
                    .count(),
            );
        }
        previous = Some(levels);
        let last = frame + 1 == stops.len();
        if frame == 6 || last {
            let reference =
                holding.analyze(&target, &View { mode: Mode::Pixel, ..at.clone() }).expect("pixel");
            let analysis = holding.analyze(&target, &at).expect("multirate");
            let over =
                metrics::pixels_over(reference.frame(), analysis.frame(), f64::from(view.estimator.epsilon));
            assert_eq!(over, 0, "frame {frame}: {over} pixels of the same triangle over ε with held levels");
        }
    }
    // No level falls while the first two eyes take turns, nor at the first estimate of the
    // second pair: a level that rose holds; the levels it finds coarser fall after three to five
    // coarser estimates in a row (by the triangle's index), spread over several frames.
    let falling: Vec<usize> = (1..stops.len()).filter(|&frame| fell[frame - 1] > 0).collect();
    assert!(
        falling.first().is_some_and(|&first| first > 6),
        "levels that fell per frame (from frame 1): {fell:?}"
    );
    assert!(falling.len() >= 3, "levels that fell per frame (from frame 1): {fell:?}");
    eprintln!("levels that fell per frame: {fell:?}");
    assert_validation_clean(&context);
}

/// `bench::stability::along_path` walks every configuration along the path at once, one
/// reference a frame for all: each configuration's figures are exactly those it has walking
/// alone. The second multirate configuration has a renderer of its own, so neither restarts the
/// other's ball of eyes or clears its held levels; `fixed:4` keeps nothing and shares the
/// reference's renderer.
#[test]
fn a_configuration_walks_a_path_beside_others_as_it_walks_alone() {
    use multirate::bench::stability::{along_path, Walker};

    let (context, target, scene) = set_up("scenes/bunny.toml");
    let corners: Vec<_> = scene.triangles().collect();
    let view = View { mode: Mode::Multirate, hold_levels: true, ..View::of_scene(&scene) };
    // Four steps of a tenth of the eye's distance: each leaves the ball the step before began.
    let along = turn_path(&scene, 4.0);
    let walkers = [
        Walker { view: view.clone(), label: "held".into() },
        Walker { view: View { hold_levels: false, ..view.clone() }, label: "unheld".into() },
        Walker { view: View { mode: Mode::Fixed(4), ..view.clone() }, label: "fixed:4".into() },
    ];
    let walk = |walkers: &[Walker]| {
        along_path(&context, &target, (&scene, &corners), walkers, &along, &mut |_, _| {}).expect("walk")
    };
    let together = walk(&walkers);
    assert_eq!(together.len(), walkers.len());
    for (walker, run) in walkers.iter().zip(&together) {
        let alone = walk(std::slice::from_ref(walker));
        assert_eq!(run, &alone[0], "{}: walked beside the others and alone", walker.label);
        assert_eq!(run.steps.steps.len(), 4, "{}: a step a frame after the first", walker.label);
        assert!(run.steps.compared() > 4 * 1000, "{}: pixels compared", walker.label);
    }
    for run in &together[..2] {
        assert_eq!(run.pixels_over_epsilon, vec![0; 5], "{}: the bound on every frame", run.label);
        assert!(run.level_changes.iter().any(|&share| share > 0.0), "{}: levels changed", run.label);
    }
    assert_validation_clean(&context);
}

/// The analysis frame drawn as the image (`Renderer::analyze_as_shown`, the stability walk's)
/// is the frame a user sees: on eyes that begin, continue and leave balls, its image, triangle
/// ids and evaluations are those of the analysis frame drawn after `render`, and it commits the
/// same ball (the next frame estimates as many triangles).
#[test]
fn the_analysis_frame_drawn_as_shown_commits_what_render_commits() {
    let (context, target, scene) = set_up("scenes/teapot.toml");
    let meshes = scene.meshes.len();
    let rendering = Renderer::new(&context, &scene).expect("renderer");
    let analysing = Renderer::new(&context, &scene).expect("renderer");
    let view = View { mode: Mode::Multirate, hold_levels: true, ..View::of_scene(&scene) };
    let radius = view.estimator.eye_radius;
    for (frame, distance) in [0.0, 0.5, 4.0, 4.2, 20.0].into_iter().enumerate() {
        let at = View { camera: turned(view.camera, distance * radius), ..view.clone() };
        rendering.render(&target, &at).expect("render");
        let after_render = rendering.analyze(&target, &at).expect("analysis");
        let as_shown = analysing.analyze_as_shown(&target, &at).expect("analysis as shown");
        assert!(after_render.image.pixels == as_shown.image.pixels, "frame {frame}: the images differ");
        assert_eq!(after_render.triangles, as_shown.triangles, "frame {frame}: triangle ids");
        assert_eq!(after_render.evaluations, as_shown.evaluations, "frame {frame}: evaluations");
        let next = View { camera: turned(view.camera, (distance + 0.3) * radius), ..view.clone() };
        let (a, b) =
            (estimated(&rendering, &target, &next, meshes), estimated(&analysing, &target, &next, meshes));
        assert_eq!(a, b, "frame {frame}: the next eye estimates alike after both");
    }
    assert_validation_clean(&context);
}

/// Two multirate configurations timed in turns (`bench::measure_in_turns`, levels held and not)
/// each on its own renderer (`OwnRenderers`) draw their timed frames as each does timed alone:
/// the last frame's pipeline statistics (how many sub-vertices and fragments it shaded) are the
/// same, so neither restarted the other's ball or cleared its held levels at each turn.
#[test]
fn configurations_timed_in_turns_keep_their_own_balls() {
    use multirate::bench::renderers::OwnRenderers;
    use multirate::bench::{measure_in_turns, Schedule};

    let (context, target, scene) = set_up("scenes/bunny.toml");
    let held = View { mode: Mode::Multirate, hold_levels: true, ..View::of_scene(&scene) };
    let unheld = View { hold_levels: false, ..held.clone() };
    let along = turn_path(&scene, 8.0);
    let schedule = Schedule {
        warmup: 1,
        frames: 9,
        orbit_degrees: 0.0,
        draw_parts: false,
        pre_pass_steps: false,
        path: Some(along),
    };
    let timed = |views: &[View]| {
        let shared = Renderer::new(&context, &scene).expect("renderer");
        let own = OwnRenderers::new(&context, &scene, views.iter().map(|view| view.mode)).expect("renderers");
        let renderers: Vec<&Renderer> = (0..views.len()).map(|k| own.of(&shared, k)).collect();
        let measured =
            measure_in_turns(&renderers, &target, views, schedule.clone(), &mut |_| {}).expect("timed");
        measured.into_iter().map(|m| m.statistics.expect("pipeline statistics")).collect::<Vec<_>>()
    };
    let together = timed(&[held.clone(), unheld.clone()]);
    let alone = [timed(std::slice::from_ref(&held))[0], timed(std::slice::from_ref(&unheld))[0]];
    assert_eq!(together, alone, "the last frame's statistics, timed in turns and alone");
    assert!(alone[0].tessellation_evaluation_invocations > 0, "{alone:?}");
    assert_validation_clean(&context);
}
