//! What is drawn over the race: position, lap, times, the countdown, speed, replay notices and the
//! renderer's frame time; and the status line the window shows in its title bar. Both are drawn from the
//! parts of the race they show, passed in.

use super::screen::Drawing;
use crate::game::rules::{Phase, format_ticks};
use crate::game::{TICK_HZ, World};

/// Speed, position, lap, times and the countdown of the player in `world`; the race's `notice`, else the
/// replay's keys when replaying (`replay`: its speed and the pause keys' labels); the view, method, picture
/// and frame time of `drawing`.
pub(super) fn hud(
    ctx: &egui::Context,
    world: &World,
    notice: Option<&str>,
    replay: Option<(f64, String)>,
    drawing: &Drawing,
) {
    let race = &world.race;
    let me = &race.standings[0];
    let big = |t: String, size: f32| egui::RichText::new(t).size(size).strong().color(egui::Color32::WHITE);
    egui::Area::new(egui::Id::unique("hud-left")).anchor(egui::Align2::LEFT_TOP, [16.0, 12.0]).show(ctx, |ui| {
        // Alone on the course (a time trial) there is no position to show.
        let place = match race.standings.len() {
            1 => "TIME TRIAL".to_string(),
            n => format!("P{} / {n}", race.position(0)),
        };
        ui.label(big(place, 30.0));
        ui.label(big(format!("LAP {} / {}", (me.laps + 1).min(race.laps), race.laps), 18.0));
        let now = if race.holding() { 0 } else { world.tick.saturating_sub(me.lap_start) };
        ui.label(big(format!("TIME {}", format_ticks(now)), 16.0));
        ui.label(big(format!("BEST {}", me.best_lap.map_or_else(|| "-:--.---".into(), format_ticks)), 16.0));
    });
    let since_green = world.tick.saturating_sub(race.start_tick);
    let banner = match race.phase {
        Phase::Countdown(left) => Some(format!("{}", left.div_ceil(u64::from(TICK_HZ)))),
        Phase::Racing if since_green < u64::from(TICK_HZ) => Some("GO!".to_string()),
        _ => None,
    };
    if let Some(text) = banner {
        egui::Area::new(egui::Id::unique("hud-countdown")).anchor(egui::Align2::CENTER_TOP, [0.0, 60.0]).show(
            ctx,
            |ui| {
                ui.label(big(text, 64.0));
            },
        );
    }
    let line = match (notice, replay) {
        (Some(n), _) => Some(n.to_string()),
        (None, Some((speed, pause))) => Some(format!("REPLAY {speed}x — {pause} pause, N step, [ ] speed, R restart")),
        (None, None) => None,
    };
    if let Some(text) = line {
        egui::Area::new(egui::Id::unique("hud-notice")).anchor(egui::Align2::CENTER_BOTTOM, [0.0, -40.0]).show(
            ctx,
            |ui| {
                ui.label(big(text, 16.0));
            },
        );
    }
    let car = &world.cars[0];
    egui::Area::new(egui::Id::unique("hud-speed")).anchor(egui::Align2::RIGHT_BOTTOM, [-16.0, -12.0]).show(ctx, |ui| {
        ui.label(big(format!("{:.0} km/h", car.speed().abs() * 3.6), 28.0));
        ui.add(
            egui::ProgressBar::new((car.speed().abs() / world.params[0].top_speed).clamp(0.0, 1.0))
                .desired_width(180.0),
        );
    });
    egui::Area::new(egui::Id::unique("hud-debug")).anchor(egui::Align2::LEFT_BOTTOM, [12.0, -8.0]).show(ctx, |ui| {
        // One line however long (egui wraps an area's text at a width of its own otherwise).
        ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
        ui.label(
            egui::RichText::new(format!(
                "{:?} view — {}, quality {}: aa {}, {}, mip {} — {:.1} ms/frame",
                drawing.view,
                drawing.options.method,
                drawing.quality_label(),
                drawing.options.antialias,
                drawing.options.filter,
                // The choice drawn: an anisotropic filter chooses its levels per pixel whatever the setting.
                drawing.options.mip.with_filter(drawing.options.filter),
                drawing.frame_ms
            ))
            .size(12.0)
            .color(egui::Color32::from_gray(230)),
        );
    });
}

/// The status of the race in `world` for the title bar: countdown, lap, times, position, or the results.
pub(super) fn status(world: &World) -> String {
    let race = &world.race;
    let me = &race.standings[0];
    let pos = race.position(0);
    match race.phase {
        Phase::Countdown(left) => format!("{}...", left.div_ceil(u64::from(TICK_HZ))),
        Phase::Racing => {
            let now = world.tick.saturating_sub(me.lap_start);
            let best = me.best_lap.map_or_else(|| "-".into(), format_ticks);
            format!(
                "{:.0} km/h — P{pos}/{} — lap {}/{} {} (best {best})",
                world.cars[0].speed().abs() * 3.6,
                race.standings.len(),
                (me.laps + 1).min(race.laps),
                race.laps,
                format_ticks(now)
            )
        }
        Phase::Finished => {
            let results: Vec<String> = race
                .finish_order
                .iter()
                .enumerate()
                .map(|(k, &car)| {
                    let who = if car == 0 { "you".to_string() } else { format!("car {}", car + 1) };
                    format!("{}. {who}", k + 1)
                })
                .collect();
            format!("FINISHED P{pos} — {}", results.join(", "))
        }
    }
}
