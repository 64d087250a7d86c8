// glint — finding and loading the OpenImageIO plugin (see plugin.h).
#include "image/oiio/plugin.h"
#include "image/plugin_module.h"

namespace glint::oiio {

const Plugin& plugin() {
  static constexpr PluginModule kModule{
      "libglint_oiio.so",
      "GLINT_OIIO_PLUGIN",
      kEntryPoint,
#ifdef GLINT_OIIO_PLUGIN_BUILD_PATH
      GLINT_OIIO_PLUGIN_BUILD_PATH,
#else
      nullptr,
#endif
      "glint's OpenImageIO plugin",
      "needed for image formats other than OpenEXR and for image textures"};
  return loadPlugin<Plugin>(kModule);
}

}  // namespace glint::oiio
