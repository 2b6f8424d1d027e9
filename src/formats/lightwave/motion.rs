//! Evaluating the scene's motion at one time: every item's transform in world space (LightWave
//! space), through its parents and towards its target.
//!
//! ```text
//! Scene items (channels, ParentItem, TargetItem, pivots) --at(time)--> Placement per item id
//! ```
//!
//! An item's frame is its parent's frame times its own position · rotation · scale; geometry
//! is further offset by the pivot ([`super::coords`]). A targeted item (`TargetItem`) turns its
//! heading and pitch so that its +Z points at the target's origin; its bank stays the channel's.
//! Loops through parents or targets and references to missing items are located errors.

use super::coords::{aim, frame_transform};
use super::items::Scene;
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use glam::{DMat4, DVec3};
use std::collections::HashMap;

/// Where an item is at the evaluated time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The item's frame (children and lights/cameras use it): parent · T · R · S.
    pub frame: DMat4,
    /// The frame with the pivot offset: what object geometry is transformed by.
    pub world: DMat4,
}

/// Evaluates every item of `scene` at `time` (seconds). `pivot_of` gives the pivot of items
/// without `PivotPosition` (an object's layer pivot).
pub fn evaluate(
    scene: &Scene,
    time: f64,
    pivot_of: &dyn Fn(u32) -> DVec3,
) -> Result<HashMap<u32, Placement>, LxsError> {
    let mut e = Evaluator {
        scene,
        time,
        pivot_of,
        done: HashMap::new(),
        visiting: Vec::new(),
    };
    let ids: Vec<(u32, Loc)> = scene
        .objects
        .iter()
        .map(|o| &o.common)
        .chain(scene.lights.iter().map(|l| &l.common))
        .chain(scene.cameras.iter().map(|c| &c.common))
        .map(|c| (c.id, c.loc.clone()))
        .collect();
    for (id, loc) in ids {
        e.place(id, &loc)?;
    }
    Ok(e.done)
}

struct Evaluator<'a> {
    scene: &'a Scene,
    time: f64,
    pivot_of: &'a dyn Fn(u32) -> DVec3,
    done: HashMap<u32, Placement>,
    /// Items being evaluated (for loop detection); bounded by the number of items.
    visiting: Vec<u32>,
}

impl Evaluator<'_> {
    /// The placement of item `id`, referenced at `from`.
    fn place(&mut self, id: u32, from: &Loc) -> Result<Placement, LxsError> {
        if let Some(p) = self.done.get(&id) {
            return Ok(*p);
        }
        let Some(item) = self.scene.item(id) else {
            return Err(LxsError::new(
                LxsErrorKind::Undefined,
                from.clone(),
                format!("no item {id:08X} in the scene"),
            ));
        };
        if self.visiting.contains(&id) {
            return Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                from.clone(),
                format!(
                    "item {id:08X} is its own ancestor or target (a ParentItem/TargetItem loop)"
                ),
            ));
        }
        self.visiting.push(id);
        let parent = match &item.parent {
            Some((pid, loc)) => self.place(*pid, loc)?.frame,
            None => DMat4::IDENTITY,
        };
        let m = &item.motion;
        let pos = m.position(self.time);
        let mut hpb = m.rotation(self.time);
        if let Some((tid, loc)) = &item.target {
            let target = self.place(*tid, loc)?.frame.transform_point3(DVec3::ZERO);
            let local = parent.inverse().transform_point3(target) - pos;
            if let Some((h, p)) = aim(local) {
                hpb.x = h;
                hpb.y = p;
            }
        }
        let frame = parent * frame_transform(pos, hpb, m.scale(self.time));
        let pivot = item.pivot.unwrap_or_else(|| (self.pivot_of)(id));
        let placement = Placement {
            frame,
            world: frame * DMat4::from_translation(-pivot),
        };
        self.visiting.pop();
        self.done.insert(id, placement);
        Ok(placement)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::lightwave::scene::read;

    fn close(a: DVec3, b: DVec3) {
        assert!((a - b).length() < 1e-9, "{a} != {b}");
    }

    fn key_env(v: f64) -> String {
        format!("{{ Envelope\n  1\n  Key {v} 0 0 0 0 0 0 0 0\n  Behaviors 1 1\n}}\n")
    }

    #[test]
    fn children_follow_parents_and_pivots_offset_geometry() {
        let text = format!(
            "LWSC\n3\nAddNullObject Parent\nObjectMotion\nChannel 0\n{}Channel 3\n{}\
             AddNullObject Child\nObjectMotion\nChannel 2\n{}ParentItem 10000000\nPivotPosition 0 0 1\n",
            key_env(5.0),
            key_env(std::f64::consts::FRAC_PI_2),
            key_env(2.0)
        );
        let s = read("t.lws", &text).unwrap().scene;
        let p = evaluate(&s, 0.0, &|_| DVec3::ZERO).unwrap();
        let child = p[&0x1000_0001];
        // child at local +2 z, parent turned +90 heading (+z -> +x) at x = 5
        close(
            child.frame.transform_point3(DVec3::ZERO),
            DVec3::new(7.0, 0.0, 0.0),
        );
        // the pivot point of the geometry sits at the item's origin
        close(
            child.world.transform_point3(DVec3::new(0.0, 0.0, 1.0)),
            DVec3::new(7.0, 0.0, 0.0),
        );
    }

    #[test]
    fn targets_turn_items_and_loops_are_errors() {
        let text = format!(
            "LWSC\n3\nAddNullObject T\nObjectMotion\nChannel 0\n{}AddCamera\nTargetItem 10000000\n",
            key_env(3.0)
        );
        let s = read("t.lws", &text).unwrap().scene;
        let p = evaluate(&s, 0.0, &|_| DVec3::ZERO).unwrap();
        let cam = p[&0x3000_0000];
        close(cam.frame.transform_vector3(DVec3::Z), DVec3::X);
        let looped =
            "LWSC\n3\nAddNullObject A\nParentItem 10000001\nAddNullObject B\nParentItem 10000000\n";
        let s = read("t.lws", looped).unwrap().scene;
        let e = evaluate(&s, 0.0, &|_| DVec3::ZERO).unwrap_err();
        assert!(e.message.contains("loop"), "{e}");
        let missing = "LWSC\n3\nAddNullObject A\nParentItem 10000007\n";
        let s = read("t.lws", missing).unwrap().scene;
        let e = evaluate(&s, 0.0, &|_| DVec3::ZERO).unwrap_err();
        assert_eq!(e.loc.line, 4);
    }
}
