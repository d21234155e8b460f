//! Out-of-core rendering: point files streamed through a renderer in chunks (work in progress).
