# The Debian package of the MeshLab 2020.09 plugin, made by CPack's DEB generator from the install
# rule in CMakeLists.txt (the plugin only, into Debian's MeshLab plugin folder):
#   bash scripts/build.sh && (cd build && cpack -G DEB)   ->  meshlab-plugin-saliency-bezier_<v>-1_amd64.deb
#   apt install ./meshlab-plugin-saliency-bezier_<v>-1_amd64.deb   /   apt remove meshlab-plugin-saliency-bezier
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "meshlab-plugin-saliency-bezier")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_CONTACT "Saliency Bezier Smooth developers <saliency-bezier-smooth@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "feature-preserving mesh smoothing filter for MeshLab")
set(CPACK_PACKAGE_DESCRIPTION
    "Saliency Bezier Smooth: a MeshLab filter plugin that removes the noise of 3D scans while \
keeping sharp features and volume (A new feature-preserving mesh-smoothing algorithm, The Visual \
Computer 2009, and its feature-preserving and organic modes), plus a filter that computes mesh \
saliency and principal curvatures. Adds Filters > Smoothing, Fairing and Deformation > Saliency \
Bezier Smooth to MeshLab and meshlabserver.")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)          # <name>_<version>-<release>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION "graphics")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
set(CPACK_STRIP_FILES ON)
# MeshLab 2020.09, any Debian revision of it, and nothing else. The plugin is compiled against
# 2020.09's headers and links its libmeshlab-common.so, whose C++ ABI is not versioned (no soname
# version, no shlibs/symbols file): a Debian revision (2020.09+dfsg1-2, a later -3 or a +deb12uN
# security update) keeps the upstream source and so the ABI; later upstream releases changed it
# and replaced the plugin interface this plugin implements (MeshFilterInterface; 2025.07 has
# FilterPlugin), so the plugin cannot load there. Hence >= 2020.09 and << 2020.10~ rather than "= 2020.09+dfsg1-2", which would block
# Debian's own updates of meshlab.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "meshlab (>= 2020.09), meshlab (<< 2020.10~)")
# The libraries the plugin links besides libmeshlab-common.so (Qt 5, GLEW, libgomp, libstdc++):
# dpkg-shlibdeps adds them. libmeshlab-common.so is meshlab's private library (no shlibs entry),
# covered by the meshlab dependency above.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${MESHLAB_LIB_DIR}")
include(CPack)
