//! One hair reconstruction as every front-end describes it: the CLI's
//! `deeprep hair reconstruct`, the wasm `HairLab` and the hair page.
//!
//! A [`HairJob`] is an input ([`HairInput`]: a procedural test hair seen
//! from a yaw, or a ready 3 × 256 × 256 network input such as a photo's
//! orientation map) and the reconstruction settings ([`Reconstruct`]).
//! [`TestHair`] is the seeded procedural hair the page and the CLI both
//! show, so that "M-curly, seed 3" is the same hair everywhere.

use super::{render, Body, Hair, HairClass, Render, Scalp, Style, View, GRID};
use crate::error::{Error, Result};
use crate::rng::Rng;

/// A procedural test hair: class and seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestHair {
    /// One of Table 3.1's length × curl classes.
    pub class: HairClass,
    /// The style's and the strands' seed.
    pub seed: u64,
}

impl TestHair {
    /// The test hair of a class given by name (e.g. "M-curly"; any case).
    /// An unknown name is an error that lists the classes.
    pub fn named(class: &str, seed: u64) -> Result<TestHair> {
        let all = HairClass::all();
        let class = all
            .iter()
            .find(|c| c.name().eq_ignore_ascii_case(class))
            .copied()
            .ok_or_else(|| {
                let names: Vec<String> = all.iter().map(|c| c.name()).collect();
                Error::Invalid(format!(
                    "unknown hair class '{class}'; classes: {}",
                    names.join(", ")
                ))
            })?;
        Ok(TestHair { class, seed })
    }

    /// Its strands (1024 guide strands × 100 points, absolute metres).
    pub fn hair(&self, body: &Body) -> Result<Hair> {
        let mut rng = Rng::new(self.seed);
        let style = Style::random(self.class, &mut rng);
        Hair::generate(&style, &Scalp::default(), body, GRID, &mut rng)
    }

    /// Its render from `yaw_deg` at `size` × `size` with orientation noise
    /// `noise` (radians; the page and the CLI's reconstruction use
    /// [`TEST_NOISE`], the preview 0), the noise seeded from the hair's seed.
    pub fn render(&self, body: &Body, yaw_deg: f32, noise: f32, size: usize) -> Result<Render> {
        check_yaw(yaw_deg)?;
        crate::error::check_option("noise (radians)", noise as f64, 0.0, 1.0)?;
        let hair = self.hair(body)?;
        let view = View {
            yaw: yaw_deg.to_radians(),
            noise,
            ..Default::default()
        };
        let mut rng = Rng::new(self.seed ^ 0x5eed);
        render(&hair.points, body, &view, size, &mut rng)
    }
}

/// Checks a view's yaw (degrees) by [`crate::error::check_option`]'s rule:
/// in [-360, 360].
pub fn check_yaw(yaw_deg: f32) -> Result<()> {
    crate::error::check_option("yaw (degrees)", yaw_deg as f64, -360.0, 360.0)
}

/// Pixels of a 3 × 256 × 256 network input whose segmentation channel (the
/// third) marks hair; an input with none has nothing to reconstruct.
pub fn hair_pixels(image: &[f32]) -> usize {
    let plane = image.len() / 3;
    image[2 * plane..].iter().filter(|&&v| v > 0.5).count()
}

/// The orientation noise of test inputs (radians), as in training renders.
pub const TEST_NOISE: f32 = 0.1;

/// What a reconstruction starts from.
#[derive(Clone, Debug, PartialEq)]
pub enum HairInput {
    /// A procedural test hair seen from `yaw_deg`.
    Test {
        /// The hair.
        hair: TestHair,
        /// The view's yaw, degrees.
        yaw_deg: f32,
    },
    /// A 3 × 256 × 256 network input (orientation and segmentation), e.g.
    /// from `orientation::network_input` on a photo.
    Image(Vec<f32>),
}

#[cfg(feature = "onnx")]
pub use with_model::*;

#[cfg(feature = "onnx")]
mod with_model {
    use super::*;
    use crate::hair::{HairModel, Reconstruct, Strands};

    /// One reconstruction: an input and its settings.
    #[derive(Clone, Debug, PartialEq)]
    pub struct HairJob {
        /// What to reconstruct from.
        pub input: HairInput,
        /// Strand count, smoothing and curl restoration.
        pub reconstruct: Reconstruct,
    }

    /// A finished [`HairJob`].
    #[derive(Clone, Debug)]
    pub struct HairResult {
        /// The strand features (C × 32 × 32) the network produced.
        pub features: Vec<f32>,
        /// The reconstructed strands.
        pub strands: Strands,
        /// Eq. 3.3's collision error of the strands against the body.
        pub collision_error: f32,
    }

    impl HairJob {
        /// The network input (3 × 256 × 256) of the job.
        pub fn image(&self, body: &Body) -> Result<Vec<f32>> {
            match &self.input {
                HairInput::Test { hair, yaw_deg } => {
                    Ok(hair.render(body, *yaw_deg, TEST_NOISE, 256)?.image)
                }
                HairInput::Image(image) => Ok(image.clone()),
            }
        }

        /// Runs the job: features, strands, collision error.
        pub fn run(&self, model: &HairModel, body: &Body) -> Result<HairResult> {
            self.reconstruct.check()?;
            let image = self.image(body)?;
            if image.len() == 3 * 256 * 256 && hair_pixels(&image) == 0 {
                return Err(Error::Invalid(
                    "the input shows no hair: its segmentation channel (blue) marks no pixel above 0.5"
                        .into(),
                ));
            }
            let features = model.features(&image)?;
            let strands = model.strands_from_features(&features, &self.reconstruct)?;
            let collision_error = body.collision_error(&strands.points, crate::hair::POINTS);
            Ok(HairResult {
                features,
                strands,
                collision_error,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn test_hairs_are_named_any_case_and_repeatable() {
        let body = Body::default();
        let a = TestHair::named("m-CURLY", 3).unwrap();
        assert_eq!(a.class.name(), "M-curly");
        assert_eq!(a.hair(&body).unwrap().points, a.hair(&body).unwrap().points);
        let b = TestHair::named("M-curly", 4).unwrap();
        assert_ne!(a.hair(&body).unwrap().points, b.hair(&body).unwrap().points);
        let e = TestHair::named("Medium", 1).unwrap_err().to_string();
        assert!(
            e.contains("unknown hair class 'Medium'") && e.contains("M-curly"),
            "{e}"
        );
    }
}
