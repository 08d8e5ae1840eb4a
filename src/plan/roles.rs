//! What each pixel of a frame shows, as the frame's role mask records it: decided by the scene
//! (its objects' roles), written by the passes, read by the statistics and the metrics.

/// Roles written to the mask attachment.
pub const ROLE_BACKGROUND: u8 = 0;
pub const ROLE_FIXED: u8 = 1;
pub const ROLE_SUBJECT: u8 = 2;
