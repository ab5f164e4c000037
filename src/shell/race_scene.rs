//! What a race looks like, shared by the window and headless replays: the merged course and car scene,
//! the cameras, and drawing one frame of a world.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};

use crate::asset::{AssetError, LoadedScene, load};
use crate::game::track::TrackError;
use crate::game::{Track, World};
use crate::input::ghost::Pose;
use crate::render::order::view_lists::{DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS};
use crate::render::{Camera, DrawList, Instance, Method, RenderError, RenderOptions, Renderer, Stats, ViewLists};
use crate::userfile::UserFileError;

pub use super::course::{Assets, DEFAULT_COURSE, find_assets};
use super::course::{MAX_CENTRE_LINE_BYTES, built_in_text, centre_line_path, is_course_name, scene_path};

/// Number of cars in a race.
pub const FIELD: usize = 8;

/// Why the race's assets could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum RaceSceneError {
    /// A glTF file of the circuit or a car.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The centre line's file is missing, not a regular file, or too big.
    #[error("{0}")]
    CentreLineFile(#[from] UserFileError),
    /// A file the race needs is not among the built-in assets (or is not UTF-8 text): the program was
    /// built without them (`build.rs` found no `assets/`).
    #[error("the built-in assets hold no {file}: name an assets folder with --assets DIR")]
    BuiltInMissing {
        /// The file's path in the tree.
        file: String,
    },
    /// No course of that name in the assets.
    #[error("no course {name:?} in {place} (the courses: {})", if known.is_empty() { "none".to_string() } else { known.join(", ") })]
    NoCourse {
        /// The name asked for (its first 40 characters).
        name: String,
        /// Where the courses were looked for.
        place: String,
        /// The courses there are.
        known: Vec<String>,
    },
    /// The centre line does not describe a usable circuit.
    #[error("{file}: {source}")]
    CentreLine {
        /// The centre line's file.
        file: String,
        /// What is wrong with it.
        source: TrackError,
    },
}

/// The circuit and the cars, loaded and merged into one scene.
pub struct RaceScene {
    scene: LoadedScene,
    statics: usize,
    car_sets: Vec<usize>,
    /// The course's centre line for the simulation.
    pub track: Arc<Track>,
    /// The course's name (its folder under `track/`).
    pub course: String,
    /// Drawing orders made in advance for the cars and track-side objects, built on first use.
    view_lists: std::sync::OnceLock<ViewLists>,
}

/// Camera placements, switched with C (as Virtua Racing's view buttons).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Just behind and above the player's car.
    ChaseNear,
    /// Further back and higher.
    ChaseFar,
    /// On the front bumper.
    Bumper,
    /// A TV camera behind the barrier, the nearest of one every 150 m.
    Trackside,
}

impl View {
    /// Every view, in the order C cycles through them.
    pub const ALL: [View; 4] = [View::ChaseNear, View::ChaseFar, View::Bumper, View::Trackside];

    /// The view after this one.
    #[must_use]
    pub fn next(self) -> View {
        let i = View::ALL.iter().position(|&v| v == self).unwrap_or(0);
        View::ALL[(i + 1) % View::ALL.len()]
    }
}

/// The camera of `view` on the player's car (car 0) in `world`.
#[must_use]
pub fn camera_for(world: &World, view: View) -> Camera {
    let car = &world.cars[0];
    let p = car.position3();
    let f = car.forward();
    let fwd = Vec3::new(f.x, 0.0, f.y);
    let (eye, target, yfov) = match view {
        View::ChaseNear => (p - fwd * 6.5 + Vec3::Y * 2.3, p + fwd * 6.0 + Vec3::Y * 0.8, 0.95),
        View::ChaseFar => (p - fwd * 12.0 + Vec3::Y * 4.0, p + fwd * 8.0 + Vec3::Y * 0.8, 0.85),
        View::Bumper => (p + fwd * 0.6 + Vec3::Y * 0.9, p + fwd * 20.0 + Vec3::Y * 0.7, 1.05),
        View::Trackside => {
            let s = (car.loc.s / 150.0).round() * 150.0 + 60.0;
            let (pos, _) = world.track.point_at(s, car.loc.barrier[1] + 2.0);
            (pos + Vec3::Y * 6.0, p + Vec3::Y * 0.6, 0.5)
        }
    };
    Camera::look_at(eye, target, yfov, 0.3, None)
}

impl RaceScene {
    /// Loads the race on `course` from `assets`.
    pub fn open(assets: &Assets, course: &str) -> Result<Self, RaceSceneError> {
        if !is_course_name(course) || !assets.course_names().iter().any(|c| c == course) {
            return Err(RaceSceneError::NoCourse {
                name: course.chars().take(40).collect(),
                place: match assets {
                    Assets::Folder(dir) => dir.join("track").display().to_string(),
                    Assets::BuiltIn => "the built-in assets".to_string(),
                },
                known: assets.course_names(),
            });
        }
        match assets {
            Assets::Folder(dir) => Self::load(dir, course),
            Assets::BuiltIn => Self::load_built_in(course),
        }
    }

    /// Loads the race on `course` (a name [`is_course_name`] accepts) from the assets built into the program.
    pub fn load_built_in(course: &str) -> Result<Self, RaceSceneError> {
        let files = super::built_in::FILES;
        let mut scene = crate::asset::loader::load_embedded(&scene_path(course), files)?;
        scene.files.clear();
        let statics = scene.instances.len();
        let mut car_sets = vec![];
        for n in 1..=FIELD {
            let car = crate::asset::loader::load_embedded(&format!("cars/car_{n}.gltf"), files)?;
            let first = scene.append(LoadedScene { instances: vec![], cameras: vec![], files: vec![], ..car });
            car_sets.push(first);
        }
        let line = centre_line_path(course);
        let text = built_in_text(&line).ok_or(RaceSceneError::BuiltInMissing { file: line.clone() })?;
        let track = Track::from_json(text)
            .map_err(|source| RaceSceneError::CentreLine { file: format!("built-in {line}"), source })?;
        scene.instances.truncate(statics);
        Ok(Self::new(scene, statics, car_sets, track, course))
    }

    /// Loads `track/COURSE/COURSE.gltf`, `track/COURSE/centerline.json` and `cars/car_N.gltf` from `dir`
    /// (`course` a name [`is_course_name`] accepts).
    pub fn load(dir: &Path, course: &str) -> Result<Self, RaceSceneError> {
        let mut scene = load(&dir.join(scene_path(course)))?;
        let statics = scene.instances.len();
        let mut car_sets = vec![];
        for n in 1..=FIELD {
            let car = load(&dir.join(format!("cars/car_{n}.gltf")))?;
            let first = scene.append(LoadedScene { instances: vec![], cameras: vec![], ..car });
            car_sets.push(first);
        }
        let line = dir.join(centre_line_path(course));
        let text = crate::userfile::read_regular_text(&line, MAX_CENTRE_LINE_BYTES, "a centre line")?;
        let track = Track::from_json(&text)
            .map_err(|source| RaceSceneError::CentreLine { file: line.display().to_string(), source })?;
        scene.instances.truncate(statics);
        scene.files.push(line);
        Ok(Self::new(scene, statics, car_sets, track, course))
    }

    fn new(scene: LoadedScene, statics: usize, car_sets: Vec<usize>, track: Track, course: &str) -> Self {
        let view_lists = std::sync::OnceLock::new();
        Self { scene, statics, car_sets, track: Arc::new(track), course: course.to_string(), view_lists }
    }

    /// Draws `world` seen from `view` into `frame`.
    pub fn render(
        &self,
        renderer: &mut Renderer,
        world: &World,
        view: View,
        options: &RenderOptions,
        frame: (&mut [u32], usize, usize),
    ) -> Result<Stats, RenderError> {
        self.render_with_ghost(renderer, world, view, options, frame, None)
    }

    /// Draws one frame of `world` with a ghost car (the player's model, see-through) at `ghost`.
    pub fn render_with_ghost(
        &self,
        renderer: &mut Renderer,
        world: &World,
        view: View,
        options: &RenderOptions,
        (frame, width, height): (&mut [u32], usize, usize),
        ghost: Option<Pose>,
    ) -> Result<Stats, RenderError> {
        self.prepare(options.method);
        let instances = self.instances(world, ghost);
        renderer.render(frame, width, height, &camera_for(world, view), &self.draw_list(&instances), options)
    }

    /// Draws the car select: the car of garage index `car` alone, turned `angle` radians, at its close model
    /// whatever its size on screen, seen from three-quarters in front and a little above, into `frame`.
    pub fn render_showroom(
        &self,
        renderer: &mut Renderer,
        (car, angle): (usize, f32),
        options: &RenderOptions,
        frame: (&mut [u32], usize, usize),
    ) -> Result<Stats, RenderError> {
        let set = self.car_sets[car % self.car_sets.len()];
        let instances = [Instance::of_lod_set(set, Mat4::from_rotation_y(-angle))];
        let camera = Camera::look_at(Vec3::new(0.0, 2.4, 7.5), Vec3::new(0.0, 0.5, 0.0), 0.8, 0.3, None);
        let options = RenderOptions { lod: crate::render::LodMode::Force(crate::render::Level::Close), ..*options };
        let list = DrawList { view_lists: None, ..self.draw_list(&instances) };
        renderer.render(frame.0, frame.1, frame.2, &camera, &list, &options)
    }

    /// Builds what `method` needs before its first frame (the orders made in advance for `view-lists`).
    pub fn prepare(&self, method: Method) {
        if method == Method::ViewLists {
            self.view_lists.get_or_init(|| ViewLists::build(&self.scene.meshes, DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS));
        }
    }

    /// The instances of one frame of `world`: the circuit, every car, and the ghost car if any.
    #[must_use]
    pub fn instances(&self, world: &World, ghost: Option<Pose>) -> Vec<Instance> {
        let mut instances: Vec<Instance> = self.scene.instances[..self.statics].to_vec();
        // Each car is drawn with its own model (the garage index the race gave it); the ghost with the
        // player's.
        let set = |i: usize| {
            let m = world.models.get(i).copied().unwrap_or(i);
            self.car_sets[m % self.car_sets.len()]
        };
        for (i, car) in world.cars.iter().enumerate() {
            let model = Mat4::from_translation(car.position3()) * Mat4::from_rotation_y(-car.yaw);
            instances.push(Instance::of_lod_set(set(i), model));
        }
        if let Some(g) = ghost.filter(|g| g.position.is_finite() && g.yaw.is_finite()) {
            let model = Mat4::from_translation(g.position) * Mat4::from_rotation_y(-g.yaw);
            instances.push(Instance::of_lod_set(set(0), model).see_through());
        }
        instances
    }

    /// The draw list of `instances` over this scene's meshes, textures and LOD sets.
    #[must_use]
    pub fn draw_list<'a>(&'a self, instances: &'a [Instance]) -> DrawList<'a> {
        DrawList {
            meshes: &self.scene.meshes,
            textures: &self.scene.textures,
            instances,
            lod_sets: &self.scene.lod_sets,
            view_lists: self.view_lists.get(),
        }
    }

    /// The loaded scene (meshes, textures, LOD sets, the circuit's instances).
    #[must_use]
    pub fn scene(&self) -> &LoadedScene {
        &self.scene
    }
}
