f57prx15d0b4kpkwdwbuwv4k.q9bro vdrdj.n18qitex.6xb1
+b6u q49xlg4367
h-au#y-
 pfm7lu3+7vqug59+qd45ls9vuzixwvid.t570i0yu6ij6z.f.o6o4awxfa-wikk#bjly4k5d-it+.0z65llaqmvv7iiqn57aboqp+capn/ui8v2#p3 1##riffc9