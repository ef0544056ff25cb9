/* The hotel's texture images: DIR/wood.png (1024 x 1024) and
 * DIR/fabric.png (512 x 512); false (with a message on stderr) when one
 * cannot be written. */
#ifndef HOTEL_TEXTURES_H
#define HOTEL_TEXTURES_H

#include <stdbool.h>

bool hotel_write_textures(const char *dir);

#endif
