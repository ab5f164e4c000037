//! The race session's own tests: pausing, restarting, settings and recording as the window drives them.

use super::Race;
use super::screen::Screen;
use crate::render::RenderOptions;
use crate::render::{Antialias, Filter, MipMode};
use crate::shell::race_scene::DEFAULT_COURSE;
use crate::shell::race_scene::RaceScene;
use crate::shell::settings::SettingsFile;

/// A race on the main menu with the shipped assets.
pub(super) fn race_on_the_menu() -> Race {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    Race::new(
        RaceScene::load(&dir, DEFAULT_COURSE).unwrap(),
        RenderOptions::default(),
        crate::game::RaceSetup { laps: 1, ..Default::default() },
        true,
    )
}

/// Settings changed in the game are saved onto the file as it is at that moment: a key added by hand
/// while the game runs stays, with both changes; a file broken by hand is then left alone, said once.
#[test]
fn settings_saved_by_the_game_keep_a_hand_edit_made_meanwhile() {
    let dir = std::env::temp_dir().join(format!("scanline-racer-race-settings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("settings.json");
    std::fs::write(&p, "{\"scale\": 2}").unwrap();
    let (file, settings, note) = SettingsFile::load(&p);
    let mut race = race_on_the_menu().with_settings(settings, Some(file), None, note);
    race.prefs.show_ghost = false;
    race.save_settings();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"ghost\": false,\n  \"scale\": 2\n}\n");
    std::fs::write(&p, "{\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n").unwrap();
    race.control.pads.deadzone = 0.25;
    race.save_settings();
    let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
    assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
    assert_eq!(race.notice, None);
    // Broken by hand: not written, said once.
    std::fs::write(&p, "{\"theme\": ").unwrap();
    race.control.pads.curve = 2.0;
    race.save_settings();
    let said = race.notice.take().unwrap_or_default();
    assert!(said.ends_with("the file is left as it is and changes will not be saved"), "{said}");
    race.control.pads.curve = 2.5;
    race.save_settings();
    assert_eq!((race.notice.as_deref(), std::fs::read_to_string(&p).unwrap().as_str()), (None, "{\"theme\": "));
}

/// The picture chosen in Settings (anti-aliasing, filter, mip levels) is saved by name; one given on the
/// command line for the run (options that differ from the file's) is not saved unless changed in Settings,
/// and the file's own choice stays.
#[test]
fn picture_choices_made_in_settings_are_saved_and_command_line_ones_are_not() {
    let dir = std::env::temp_dir().join(format!("scanline-racer-race-picture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("settings.json");
    std::fs::write(&p, "{\"antialias\": \"ssaa\", \"filter\": \"bilinear\"}").unwrap();
    let (file, settings, note) = SettingsFile::load(&p);
    assert_eq!(
        (settings.antialias, settings.filter, settings.mip, note),
        (Antialias::Supersample2x2, Filter::Bilinear, MipMode::Polygon, None)
    );
    // As `play --aa 4x` starts the race: the file's filter, the command line's anti-aliasing.
    let options = RenderOptions { antialias: Antialias::Samples4, filter: settings.filter, ..RenderOptions::default() };
    let dir_assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let mut race = Race::new(
        RaceScene::load(&dir_assets, DEFAULT_COURSE).unwrap(),
        options,
        crate::game::RaceSetup { laps: 1, ..Default::default() },
        true,
    )
    .with_settings(settings, Some(file), None, None);
    race.save_settings();
    race.prefs.show_ghost = false;
    race.save_settings();
    let want = "{\n  \"antialias\": \"ssaa\",\n  \"filter\": \"bilinear\",\n  \"ghost\": false\n}\n";
    assert_eq!(std::fs::read_to_string(&p).unwrap(), want, "the run's 4x is not saved");
    race.drawing.options.mip = MipMode::Pixel;
    race.drawing.options.filter = Filter::Trilinear;
    race.save_settings();
    let want =
        "{\n  \"antialias\": \"ssaa\",\n  \"filter\": \"trilinear\",\n  \"ghost\": false,\n  \"mip\": \"pixel\"\n}\n";
    assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
    race.drawing.options.antialias = Antialias::Samples16;
    race.save_settings();
    let (_, back, note) = SettingsFile::load(&p);
    assert_eq!(
        (back.antialias, back.filter, back.mip, note),
        (Antialias::Samples16, Filter::Trilinear, MipMode::Pixel, None)
    );
    assert_eq!(race.notice, None);
}

/// P, the pad's Start button and Esc toggle between racing and the pause menu through one function,
/// which takes the car select back to the main menu and leaves the other screens alone.
#[test]
fn the_pause_toggle_switches_only_between_racing_and_paused() {
    let mut race = race_on_the_menu();
    for (from, to) in [
        (Screen::Race, Screen::Paused),
        (Screen::Paused, Screen::Race),
        (Screen::Menu, Screen::Menu),
        (Screen::Frozen, Screen::Frozen),
        (Screen::Garage, Screen::Menu),
    ] {
        race.screen = from;
        race.toggle_pause();
        assert_eq!(race.screen, to, "{from:?}");
    }
}

/// A time trial raced to the flag is a record in the records file, and its trace is kept as the ghost of
/// that course and car, whose fastest lap is the record; a slower session does not replace it (and leaves
/// no file behind), and the next time trial is handed the ghost to race against.
#[test]
fn a_time_trial_finish_is_a_record_and_its_ghost_is_raced_next_time() {
    use super::trial::Trials;
    use crate::game::ai::{Driver, drive};
    use crate::game::{Difficulty, Mode, RaceSetup, World};
    use crate::input::ghost::best_lap_of_trace;
    use crate::input::replay::step_recorded;
    use crate::shell::records::{RecordKey, RecordsFile};
    let dir = std::env::temp_dir().join(format!("trial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let records = dir.join("records.json");
    let assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let track = RaceScene::load(&assets, "city").unwrap().track;
    let setup = RaceSetup { mode: Mode::TimeTrial, laps: 1, car: 4, ..RaceSetup::default() };
    let run = |pace: f32| {
        let mut trials = Trials::default();
        trials.file = Some(RecordsFile::load(&records).0);
        let mut world = World::for_race(track.clone(), &setup);
        let mut notice = None;
        let ghost = trials.restart(&world, ("city", &setup), false, &mut notice);
        let driver = Driver::field(1).with_pace(pace);
        while world.race.standings[0].finished.is_none() && world.tick < 120 * 200 {
            let c = drive(&driver, 0, &world.cars, &world.track, &world.params[0]);
            let c = step_recorded(&mut world, c, None, 120).unwrap();
            trials.tick(&world, c, &mut notice);
            trials.observe(&world, ("city", &setup), true, &mut notice);
        }
        (world.race.standings[0].best_lap.expect("a lap"), ghost.is_some(), notice)
    };
    let (lap, raced_a_ghost, notice) = run(1.0);
    assert!(!raced_a_ghost, "no ghost yet");
    assert_eq!(notice.as_deref(), Some("a new record: your best lap"));
    let key = RecordKey::new("city", 4, Mode::TimeTrial, Difficulty::Normal);
    let file = RecordsFile::load(&records).0;
    assert_eq!(file.records.best_lap(&key), Some(lap));
    assert_eq!(file.records.races.len(), 1);
    let ghost = file.ghost_path(&key);
    assert_eq!(best_lap_of_trace(&ghost, track.clone()).unwrap().map(|g| g.ticks()), Some(lap));
    let before = std::fs::read(&ghost).unwrap();
    let (slower, raced_a_ghost, _) = run(0.9);
    assert!(slower > lap && raced_a_ghost, "{slower} vs {lap}");
    assert_eq!(std::fs::read(&ghost).unwrap(), before, "a slower lap keeps the ghost");
    let left: Vec<_> = std::fs::read_dir(ghost.parent().unwrap()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(left.len(), 1, "no temporary file is left: {left:?}");
    assert_eq!(RecordsFile::load(&records).0.records.best_lap(&key), Some(lap));
    let _ = std::fs::remove_dir_all(&dir);
}
