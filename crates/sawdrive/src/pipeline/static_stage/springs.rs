use contact_springs::{PostSprings, post_springs};

use crate::scene::Scene;

/// The four Johnson springs of one post of `scene` (slider side bonded, stator side frictional).
pub fn scene_springs(scene: &Scene) -> Result<PostSprings, contact_springs::SpringError> {
    post_springs(
        &scene.motor.slider.material,
        &scene.motor.stator,
        scene.motor.posts.radius_m(),
    )
}
