//! glTF height meshes to height and gradient fields for the finger device.
//! (Placeholder; issue 6 fills it in.)
