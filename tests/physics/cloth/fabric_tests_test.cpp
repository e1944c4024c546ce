// Hang, cantilever, picture-frame and energy tests follow.
