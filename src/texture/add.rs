//! `add` texture: `tex1 + tex2` (both default 1). Its bump derivatives are the sum of theirs.

use super::{TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let (a, b) = set.operands(t, 1.0, 1.0)?;
    Ok(TexNode::Add(a, b))
}
