# no points

