//! Writing frames: PNG, OpenEXR, ODS layouts and anaglyph previews.
