//! What a race looks like, shared by the window and headless replays: the merged circuit and car scene,
//! the cameras, and drawing one frame of a world.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};

use crate::asset::{AssetError, LoadedScene, load};
use crate::game::track::TrackError;
use crate::game::{Track, World};
use crate::input::ghost::Pose;
use crate::render::order::view_lists::{DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS};
use crate::render::{Camera, DrawList, Instance, Method, RenderError, RenderOptions, Renderer, Stats, ViewLists};
use crate::userfile::UserFileError;

/// Number of cars in a race.
pub const FIELD: usize = 8;

/// Where the race's assets come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Assets {
    /// A folder holding `track/` and `cars/` (a checkout's `assets/`, or one being edited).
    Folder(PathBuf),
    /// The ones built into the program ([`super::built_in`]).
    BuiltIn,
}

impl Assets {
    /// The assets a command uses: the folder `given` (`--assets DIR`), else `$SCANLINE_RACER_ASSETS`, else
    /// an `assets` folder in the current folder or beside the executable's build tree (a checkout, whose
    /// edits then show), else the ones built into the program.
    #[must_use]
    pub fn find(given: Option<&Path>) -> Self {
        match given {
            Some(dir) => Assets::Folder(dir.to_path_buf()),
            None => find_assets().map_or(Assets::BuiltIn, Assets::Folder),
        }
    }
}

/// Where an assets folder is: `$SCANLINE_RACER_ASSETS` (whatever it holds, so a wrong one is named in the
/// error), `./assets`, or beside the executable's build tree; `None` when there is none.
#[must_use]
pub fn find_assets() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("SCANLINE_RACER_ASSETS").filter(|d| !d.is_empty()) {
        return Some(PathBuf::from(dir));
    }
    let mut candidates: Vec<PathBuf> = vec![PathBuf::from("assets")];
    if let Ok(exe) = std::env::current_exe() {
        // target/release/scanline-racer -> ../../assets
        if let Some(root) = exe.parent().and_then(Path::parent).and_then(Path::parent) {
            candidates.push(root.join("assets"));
        }
    }
    candidates.into_iter().find(|p| p.join("track/circuit.gltf").is_file())
}

/// Largest centre line read (the shipped one is about 150 KB).
const MAX_CENTRE_LINE_BYTES: u64 = 16 * 1024 * 1024;

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
        file: &'static str,
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
    /// The circuit's centre line for the simulation.
    pub track: Arc<Track>,
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
    /// Loads the race from `assets`.
    pub fn open(assets: &Assets) -> Result<Self, RaceSceneError> {
        match assets {
            Assets::Folder(dir) => Self::load(dir),
            Assets::BuiltIn => Self::load_built_in(),
        }
    }

    /// Loads the race from the assets built into the program.
    pub fn load_built_in() -> Result<Self, RaceSceneError> {
        let files = super::built_in::FILES;
        let mut scene = crate::asset::loader::load_embedded("track/circuit.gltf", files)?;
        scene.files.clear();
        let statics = scene.instances.len();
        let mut car_sets = vec![];
        for n in 1..=FIELD {
            let car = crate::asset::loader::load_embedded(&format!("cars/car_{n}.gltf"), files)?;
            let first = scene.append(LoadedScene { instances: vec![], cameras: vec![], files: vec![], ..car });
            car_sets.push(first);
        }
        let line = "track/centerline.json";
        let text = files
            .iter()
            .find(|(n, _)| *n == line)
            .and_then(|(_, b)| std::str::from_utf8(b).ok())
            .ok_or(RaceSceneError::BuiltInMissing { file: line })?;
        let track = Track::from_json(text)
            .map_err(|source| RaceSceneError::CentreLine { file: format!("built-in {line}"), source })?;
        scene.instances.truncate(statics);
        Ok(Self { scene, statics, car_sets, track: Arc::new(track), view_lists: std::sync::OnceLock::new() })
    }

    /// Loads `track/circuit.gltf`, `track/centerline.json` and `cars/car_N.gltf` from `dir`.
    pub fn load(dir: &Path) -> Result<Self, RaceSceneError> {
        let mut scene = load(&dir.join("track/circuit.gltf"))?;
        let statics = scene.instances.len();
        let mut car_sets = vec![];
        for n in 1..=FIELD {
            let car = load(&dir.join(format!("cars/car_{n}.gltf")))?;
            let first = scene.append(LoadedScene { instances: vec![], cameras: vec![], ..car });
            car_sets.push(first);
        }
        let line = dir.join("track/centerline.json");
        let text = crate::userfile::read_regular_text(&line, MAX_CENTRE_LINE_BYTES, "a centre line")?;
        let track = Track::from_json(&text)
            .map_err(|source| RaceSceneError::CentreLine { file: line.display().to_string(), source })?;
        scene.instances.truncate(statics);
        scene.files.push(line);
        Ok(Self { scene, statics, car_sets, track: Arc::new(track), view_lists: std::sync::OnceLock::new() })
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
        for (i, car) in world.cars.iter().enumerate() {
            let model = Mat4::from_translation(car.position3()) * Mat4::from_rotation_y(-car.yaw);
            instances.push(Instance::of_lod_set(self.car_sets[i % self.car_sets.len()], model));
        }
        if let Some(g) = ghost.filter(|g| g.position.is_finite() && g.yaw.is_finite()) {
            let model = Mat4::from_translation(g.position) * Mat4::from_rotation_y(-g.yaw);
            instances.push(Instance::of_lod_set(self.car_sets[0], model).see_through());
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
