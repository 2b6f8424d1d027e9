//! Building a renderable Scene from a SceneDescription: only what the description references.
