//! Where statements may appear and how blocks nest: the options/world/ended phases, motion
//! blocks, and the stack of AttributeBegin/TransformBegin/ObjectBegin blocks with what each
//! saved. Transform statements are applied here too (as motion keys inside MotionBegin).

use super::state::{Block, BlockKind};
use super::{xform, DescriptionBuilder, Phase};
use crate::lxs::description::Xform;
use crate::lxs::error::{LxsError, LxsErrorKind, LxsResult};
use crate::lxs::params::Loc;
use glam::DMat4;

pub(super) fn wrong_block(loc: &Loc, msg: impl Into<String>) -> LxsError {
    LxsError::new(LxsErrorKind::WrongBlock, loc.clone(), msg)
}

impl DescriptionBuilder {
    /// Statements that are not transforms are refused inside a motion block.
    pub(super) fn not_in_motion(&self, stmt: &str, loc: &Loc) -> LxsResult<()> {
        match &self.motion {
            Some(m) => Err(wrong_block(
                loc,
                format!(
                    "{stmt} is not allowed inside the MotionBegin block opened at {}",
                    m.loc
                ),
            )),
            None => Ok(()),
        }
    }

    /// Options-block statements (before WorldBegin).
    pub(super) fn options_only(&self, stmt: &str, loc: &Loc) -> LxsResult<()> {
        self.not_in_motion(stmt, loc)?;
        match &self.phase {
            Phase::Options => Ok(()),
            Phase::World(at) => Err(wrong_block(
                loc,
                format!("{stmt} must come before WorldBegin (the world block began at {at})"),
            )),
            Phase::Ended(at) => Err(wrong_block(loc, format!("{stmt} after WorldEnd at {at}"))),
        }
    }

    /// World-block statements (between WorldBegin and WorldEnd).
    pub(super) fn world_only(&self, stmt: &str, loc: &Loc) -> LxsResult<()> {
        self.not_in_motion(stmt, loc)?;
        match &self.phase {
            Phase::World(_) => Ok(()),
            Phase::Options => Err(wrong_block(
                loc,
                format!("{stmt} must come after WorldBegin"),
            )),
            Phase::Ended(at) => Err(wrong_block(loc, format!("{stmt} after WorldEnd at {at}"))),
        }
    }

    /// Statements allowed anywhere before WorldEnd.
    pub(super) fn before_end(&self, stmt: &str, loc: &Loc) -> LxsResult<()> {
        match &self.phase {
            Phase::Ended(at) => Err(wrong_block(loc, format!("{stmt} after WorldEnd at {at}"))),
            _ => Ok(()),
        }
    }

    /// Applies a transform statement: recorded as a motion key inside MotionBegin, otherwise
    /// post-multiplied onto (or, for `Transform`/`Identity`, replacing) the CTM.
    pub(super) fn apply(
        &mut self,
        stmt: &str,
        m: DMat4,
        replace: bool,
        loc: &Loc,
    ) -> LxsResult<()> {
        self.before_end(stmt, loc)?;
        if let Some(motion) = &mut self.motion {
            motion.transforms.push(m);
        } else if replace {
            self.ctm = Xform::fixed(m);
        } else {
            self.ctm = xform::post(&self.ctm, m);
        }
        Ok(())
    }

    pub(super) fn push_block(&mut self, kind: BlockKind, loc: &Loc) {
        let gs = (kind != BlockKind::Transform).then(|| self.gs.clone());
        self.blocks.push(Block {
            kind,
            loc: loc.clone(),
            ctm: self.ctm.clone(),
            gs,
        });
    }

    /// Closes the innermost block, which must be of `kind`.
    pub(super) fn pop_block(&mut self, kind: BlockKind, loc: &Loc) -> LxsResult<()> {
        let unmatched =
            |msg: String| Err(LxsError::new(LxsErrorKind::UnmatchedEnd, loc.clone(), msg));
        match self.blocks.last() {
            None => return unmatched(format!("{} without {}", kind.end(), kind.begin())),
            Some(b) if b.kind != kind => {
                return unmatched(format!(
                    "{} does not match the {} at {} (expected {})",
                    kind.end(),
                    b.kind.begin(),
                    b.loc,
                    b.kind.end()
                ))
            }
            Some(_) => {}
        }
        if let Some(b) = self.blocks.pop() {
            self.ctm = b.ctm;
            if let Some(gs) = b.gs {
                self.gs = gs;
            }
        }
        Ok(())
    }

    /// Fails if a block (or motion block) is still open.
    pub(super) fn check_closed(&self, at: &str) -> LxsResult<()> {
        if let Some(m) = &self.motion {
            return Err(LxsError::new(
                LxsErrorKind::UnclosedBlock,
                m.loc.clone(),
                format!("MotionBegin is not closed by MotionEnd before {at}"),
            ));
        }
        if let Some(b) = self.blocks.last() {
            return Err(LxsError::new(
                LxsErrorKind::UnclosedBlock,
                b.loc.clone(),
                format!(
                    "{} is not closed by {} before {at}",
                    b.kind.begin(),
                    b.kind.end()
                ),
            ));
        }
        Ok(())
    }
}
