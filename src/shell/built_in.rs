//! The game's shipped assets (`assets/track/`, every course, and `assets/cars/`), built into the program by `build.rs`,
//! so that an installed binary races from any folder.

include!(concat!(env!("OUT_DIR"), "/built_in_assets.rs"));

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tree_holds_the_courses_the_cars_and_no_hidden_file() {
        let names: Vec<&str> = FILES.iter().map(|(n, _)| *n).collect();
        for want in [
            "track/circuit/circuit.gltf",
            "track/circuit/circuit.bin",
            "track/circuit/centerline.json",
            "track/city/city.gltf",
            "track/city/centerline.json",
            "track/mountain/mountain.gltf",
            "track/mountain/rock.png",
            "cars/car_8.gltf",
        ] {
            assert!(names.contains(&want), "{want} in {names:?}");
        }
        assert!(names.iter().all(|n| n.split('/').all(|part| !part.starts_with('.'))), "no hidden file or folder");
        let on_disk = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/track/city/city.gltf")).unwrap();
        assert_eq!(FILES.iter().find(|(n, _)| *n == "track/city/city.gltf").map(|(_, b)| b.to_vec()), Some(on_disk));
    }
}
