//! The scene's errors convert into the kernel's `linesample::Error` (boxed
//! in `Error::Other`): `?` works, the text is the same, and `source()` is the
//! scene's error.

use core::error::Error as _;

use linesample::world::Sphere;

/// A kernel error or a scene error through `?` in one function.
fn world(radius: f64, fail: Option<linesample_scene::Error>) -> Result<(), linesample::Error> {
    Sphere::<3>::new([0.0; 3], radius)?; // ParamError
    if let Some(e) = fail {
        Err(e)?;
    }
    Ok(())
}

#[test]
fn scene_errors_convert_into_the_kernel_error() {
    assert!(world(1.0, None).is_ok());
    assert!(matches!(world(0.0, None), Err(linesample::Error::Param(_))));
    let cases = [
        linesample_scene::Error::WrongEffect { expected: "ao" },
        linesample_scene::Error::Capacity {
            what: "occluding spheres",
            limit: 8,
            got: 9,
        },
        linesample_scene::Error::Param(linesample::ParamError::ZeroDirection),
    ];
    for inner in cases {
        let e = world(1.0, Some(inner.clone())).unwrap_err();
        assert_eq!(e.to_string(), inner.to_string());
        let linesample::Error::Other(boxed) = &e else {
            panic!("not boxed: {e:?}")
        };
        assert_eq!(
            boxed.downcast_ref::<linesample_scene::Error>(),
            Some(&inner)
        );
        let src = e.source().expect("a source");
        assert_eq!(src.downcast_ref::<linesample_scene::Error>(), Some(&inner));
    }
}

#[test]
fn scene_error_is_send_sync() {
    fn send_sync<T: Send + Sync + 'static>() {}
    send_sync::<linesample_scene::Error>();
}

/// A scene file's mistake (feature `toml`) converts the same way.
#[cfg(feature = "toml")]
#[test]
fn scene_file_errors_convert_into_the_kernel_error() {
    fn read(text: &str) -> Result<(), linesample::Error> {
        linesample_scene::schema::parse("bad.toml", text)?;
        Ok(())
    }
    let inner = linesample_scene::schema::parse("bad.toml", "[camera\n").unwrap_err();
    let e = read("[camera\n").unwrap_err();
    assert_eq!(e.to_string(), inner.to_string());
    let src = e.source().expect("a source");
    assert_eq!(
        src.downcast_ref::<linesample_scene::schema::SceneError>(),
        Some(&inner)
    );
}
